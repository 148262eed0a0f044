// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: geodesic distances on a triangle mesh by fast marching.
//
// Reference: R. Kimmel and J. A. Sethian, "Computing geodesic paths on manifolds", Proc. Natl.
// Acad. Sci. USA 95(15), 8431-8435, 1998. Used for the all-pairs geodesic distances of the
// geodesic canonical form (A. Elad and R. Kimmel, IEEE TPAMI 2003; Pickup et al., Pattern
// Recognition 2015, Section 3.1).
//
// What is implemented: the first-order fast marching method on a triangulated surface with unit
// speed (|grad T| = 1). Vertices are accepted in increasing order of their tentative distance
// (a binary heap, as Dijkstra). When a vertex u is accepted, every not yet accepted vertex C that
// shares a triangle (C, u, w) with it is updated:
//   - if w is accepted too, by the planar update of the paper: a plane wave T(x) = T_C + n.(x - C),
//     |n| = 1, through (A, T_A) and (B, T_B) gives a quadratic in T_C; we take its larger root and
//     accept it only if it is causal, i.e. T_C >= max(T_A, T_B) and the back-traced characteristic
//     -n lies inside the angle ACB (the update comes from within the triangle). Otherwise, and
//   - if w is not accepted, by the edge (Dijkstra) updates T_A + |AC| and T_B + |BC|.
// Obtuse triangles are handled by the paper's unfolding: for a corner C whose angle is obtuse,
// the triangles beyond the opposite edge AB are unfolded into the plane of ABC, one at a time
// across the edge the "section" crosses, until a vertex D is found inside the section (the
// directions making an acute angle with both CA and CB; at most kMaxUnfoldSteps triangles). The
// obtuse triangle is then replaced, for updates of C, by the two virtual triangles (C, A, D) and
// (C, D, B) with planar (unfolded) geometry, and the virtual edge CD gives an edge update too.
// If no such D exists (boundary reached, or the step limit), the obtuse triangle is used as it is
// (planar update when causal, else the edge fall-back). All of this is set up once per mesh
// (FastMarching) and reused for every source.
//
// Departures from the paper, and why:
// - Only accepted ("alive") vertices feed updates, as in the standard method; the paper's trial
//   values are never combined, which keeps the propagation monotone.
// - The unfolding search is bounded (kMaxUnfoldSteps triangles) so a pathological mesh cannot make
//   set-up quadratic; corners where it fails keep the edge fall-back (counted in stats()).
// - The quadratic is solved with T_A subtracted first (values relative to the smaller corner),
//   which avoids the cancellation of the textbook form when T >> edge length.
// - All-pairs distances are symmetrised: D_ij = (d(i,j) + d(j,i)) / 2. Fast marching is not
//   exactly symmetric (first-order error, O(h)); MDS needs a symmetric matrix.
// Accuracy against analytic distances on spheres, discs and obtuse lattices, with and without the
// unfolding, is checked by tests/test_geodesic_distances.cpp (figures: docs/design.md).
// Vertices not connected to the source (other components, unreferenced vertices) get +infinity.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstddef>
#include <utility>
#include <vector>

namespace canonform::surface {

/// Fast marching set-up of one mesh: the update stencils of every vertex (its triangles, with
/// obtuse corners split by unfolding), built once and reused for any number of sources. Thread
/// safe for concurrent distances_from() calls with distinct Workspaces.
class FastMarching {
public:
    /// Largest number of triangles unfolded when splitting one obtuse corner.
    static constexpr int kMaxUnfoldSteps = 12;

    /// Per-call scratch (acceptance flags and the heap); give each thread its own.
    struct Workspace {
        std::vector<unsigned char> accepted;
        std::vector<std::pair<double, int>> heap;
    };

    /// Set-up statistics.
    struct Stats {
        int obtuse_corners = 0;    ///< triangle corners with an angle above 90 degrees
        int unfolded_corners = 0;  ///< of those, split by a vertex found by unfolding
    };

    /// V: #V x 3 vertex positions; F: #F x 3 vertex indices (0-based). `unfold_obtuse` = false
    /// uses the edge fall-back only for obtuse triangles (for comparison). Throws InputError on
    /// wrong column counts, non-finite coordinates or face indices out of range.
    FastMarching(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, bool unfold_obtuse = true);

    int num_vertices() const { return n_; }
    const Stats& stats() const { return stats_; }

    /// Distances from `source` to every vertex written into `out` (size #V, units of V; 0 at the
    /// source, +infinity where unreachable), using the scratch `ws`. Throws InputError if
    /// `source` is out of range or out has the wrong size.
    void distances_from(int source, Eigen::Ref<Eigen::VectorXd> out, Workspace& ws) const;

    /// Convenience overload with its own scratch.
    Eigen::VectorXd distances_from(int source) const;

private:
    /// One directed update stencil, stored in the list of its source vertex `self`: the target
    /// C, the other triangle vertex (real or unfolded), and the planar geometry relative to C.
    struct Stencil {
        int target;        ///< C, the vertex updated
        int other;         ///< the triangle's third vertex (w)
        double len_self;   ///< |self - C|
        double len_other;  ///< |other - C|
        double dot;        ///< (self - C) . (other - C)
    };

    int n_ = 0;
    std::vector<int> offsets_;  ///< stencils of vertex v: stencils_[offsets_[v] .. offsets_[v+1])
    std::vector<Stencil> stencils_;
    Stats stats_;
};

/// Distances from one source vertex to all vertices (#V), in the units of V (+infinity where
/// unreachable). Builds a FastMarching set-up; for many sources build it once instead.
Eigen::VectorXd geodesic_distances_from(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int source);

/// Options of all_pairs_geodesic_distances().
struct GeodesicOptions {
    int threads = 0;      ///< worker threads including the caller; 0 = every hardware thread (thread_count())
    ProgressFn progress;  ///< called from the calling thread about every 1% ("geodesic distances")
};

/// All-pairs distances, #V x #V, in the units of V: symmetric (the average of d(i,j) and d(j,i)),
/// zero diagonal, +infinity between vertices of different components. One fast march per source,
/// parallel over sources (parallel_for). Results do not depend on the thread count. Throws
/// InputError on bad input, Cancelled if progress returns false (the workers are stopped first).
Eigen::MatrixXd all_pairs_geodesic_distances(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             const GeodesicOptions& options = {});

/// Peak bytes all_pairs_geodesic_distances() needs for n vertices: the n x n matrix (8 n^2), the
/// stencils (about 600 n) and per-thread scratch (about 256 n per hardware thread).
std::size_t all_pairs_geodesic_bytes(long n);

/// Estimated seconds of all_pairs_geodesic_distances() on ONE core for n vertices:
/// c * n^2 * log2(n), c = 2.0e-8 s, calibrated on meshes of 1k-5k vertices (see the .cpp); divide
/// by the thread count for the parallel wall time. `V` is accepted for future refinement and
/// currently unused (the cost depends on n for meshes of ordinary valence).
double all_pairs_geodesic_seconds_estimate(long n, const Eigen::MatrixXd* V = nullptr);

}  // namespace canonform::surface
