// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the Euclidean-distance-based canonical form of a triangle mesh.
//
// Reference: Pickup, Sun, Rosin, Martin, "Euclidean-distance-based canonical forms for non-rigid
// 3D shape retrieval", Pattern Recognition 2015, Section 4, eqs. (1)-(6) and (10).
//
// 1. Scale the mesh so the largest vertex distance to the centroid is 1.
// 2. Conformal factor phi (eqs. 7-9, conformal_factor.h), normalised to [0, 1].
// 3. Feature points F: the ceil(sqrt(N)) largest k-ring maxima of phi (feature_points.h).
// 4. SMACOF (smacof.h) on the pairs
//      mesh edges (i, j):        delta_ij = |x_i - x_j|,  w_ij = beta / delta_ij^2
//      feature pairs i<j in F:   delta_ij = alpha,        w_ij = (phi_i + phi_j) / 2
//    Variant A ("additional random feature points", beta = 10): F is topped up to exactly
//    ceil(sqrt(N)) points with seeded random vertices.
//    Variant N ("normalised weightings", eq. 10, beta = 130): F is the maxima only; edge weights
//    are divided by |E| and feature-pair weights by their sum.
//    alpha = 10 by default. SMACOF starts from the scaled mesh.
//
// Departures, and why:
// - The result is mapped back to the input's units (multiplied by the scale of step 1 and moved
//   to the input's centroid), so that edge lengths match the input; set restore_scale = false to
//   keep the paper's unit-radius frame.
// - The default variant is N: it has no random element, and on our procedural figures its
//   canonical forms of two poses agree about twice as well as variant A's (aligned RMS difference
//   0.29 of the original poses' for N, 0.50 for A; tests). A stays as the paper defines it, one
//   option away. Its weaker pose consistency is not only its random draw: with the very same
//   fill vertices in every pose it is still 0.41, with a geodesic farthest-point fill 0.41, and
//   0.35-0.65 for beta from 3 to 100. Pushing all sqrt(N) (45 at 2000 vertices) points to one
//   mutual distance alpha cannot be met in 3D (at most 4 points are equidistant), so the
//   minimiser is a frustrated compromise that small pose differences tip one way or another;
//   N's ~10 maxima sit at the limb tips, where stretching them apart is what straightens a pose.
// - On large meshes (coarse_start_from vertices and more: where the multigrid solver takes over)
//   SMACOF starts from the form of a coarser problem instead of the scaled mesh: nested
//   iteration (W. L. Briggs, V. E. Henson, S. F. McCormick, "A multigrid tutorial", 2nd ed., SIAM
//   2000, full multigrid; for MDS, M. M. Bronstein, A. M. Bronstein, R. Kimmel, I. Yavneh,
//   "Multigrid multidimensional scaling", Numer. Linear Algebra Appl. 13, 2006). Each Guttman step
//   removes the smooth, large-scale part of the error slowly, and a coarse problem resolves it for
//   a fraction of the cost. The vertices are aggregated (numerics::aggregate_vertices, strengths
//   the edges' weights 1 / delta^2); the coarse problem is step 4 on the aggregates (each at the
//   mean of its vertices, an edge between two aggregates that a mesh edge joins, each feature
//   point's aggregate a feature point with its phi), started the same way while it is still
//   large; its displacement is given to every vertex of an aggregate and averaged twice over
//   each vertex and its neighbours (an aggregate reaches two edges from its centre). SMACOF on the
//   mesh then runs from there under the same stopping rule; its configuration differs from the
//   one reached from the mesh by about what the stopping rule leaves open (docs/benchmarks.md).
// - Feature pairs whose weight is zero (both phi = 0) are left out: they contribute nothing to (1).
// - See smacof.h (sign of eq. 4, relative stopping rule) and feature_points.h (order-invariant
//   random fill).
#pragma once

#include "canonform/canonical/method_registry.h"
#include "canonform/common/errors.h"
#include "canonform/numerics/smacof.h"
#include "canonform/surface/feature_points.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace canonform::canonical {

/// The two variants of the paper (Section 4, Tables 2-5).
enum class CanonicalVariant {
    A,  ///< additional random feature points, beta = 10
    N,  ///< normalised weightings (eq. 10), beta = 130
};

/// Options of euclidean_canonical_form().
struct EuclideanCanonicalFormOptions {
    CanonicalVariant variant = CanonicalVariant::N;  ///< N: deterministic, see the header note
    double alpha = 10.0;                             ///< target distance of feature pairs (unit-radius frame)
    double beta = 0.0;  ///< edge-preservation weight; <= 0 means the variant's default
    /// Step 3: the k-ring, the seed and the count of the feature points (feature_points.h); their
    /// fill is the variant's (A: random, N: none), whatever `features.fill` says.
    surface::FeaturePointOptions features;
    numerics::SmacofOptions smacof;  ///< step 4: tolerance, iteration cap, acceleration, history (smacof.h)
    numerics::LinearSolver linear_solver =
        numerics::LinearSolver::Auto;  ///< conformal factor's and SMACOF's solver
    /// From this many vertices SMACOF starts from a coarser problem's form (header note); 0: never.
    int coarse_start_from = numerics::kMultigridFrom;
    bool restore_scale = true;  ///< return the result in the input's units and position
    bool validate = true;       ///< run validate_mesh() first (off only if the caller just did)
    int threads =
        0;  ///< threads of the multigrid solver's large sweeps (0: every core; no effect on results)
    ProgressFn progress;  ///< optional progress callback (smacof.progress is not called)
    /// Optional: step 2's conformal factor kept from an earlier form of this very mesh with the
    /// same solver (method_registry.h); the form is the same bits either way.
    ConformalFactorMemo conformal_factors;

    /// beta actually used: `beta` if positive, else 10 (A) or 130 (N).
    double effective_beta() const {
        return beta > 0 ? beta : (variant == CanonicalVariant::A ? 10.0 : 130.0);
    }
    /// The defaults of a variant, with its beta written out (what the method registry lists).
    static EuclideanCanonicalFormOptions of_variant(CanonicalVariant v) {
        EuclideanCanonicalFormOptions o;
        o.variant = v;
        o.beta = o.effective_beta();
        return o;
    }
};

/// The parameters of these options a user sets - alpha, beta, ring, seed, tolerance,
/// max_iterations, acceleration, solver - with their defaults from `defaults` (common/parameters.h;
/// the registry lists them with of_variant()'s defaults).
ParameterSet<EuclideanCanonicalFormOptions> euclidean_canonical_form_parameters(
    const EuclideanCanonicalFormOptions& defaults = {});

/// Result of euclidean_canonical_form(): the form, its feature points, the SMACOF run's statistics
/// (SmacofStatistics, in the unit-radius frame) and the timings.
struct EuclideanCanonicalFormResult : numerics::SmacofStatistics {
    Eigen::MatrixXd V;                     ///< canonical form, #V x 3 (same vertex order and faces)
    Eigen::VectorXd phi;                   ///< normalised conformal factor, #V
    std::vector<int> features;             ///< feature points (maxima first, then random fill)
    int num_maxima = 0;                    ///< local maxima among `features`
    int num_random = 0;                    ///< random fill among `features`
    double mean_relative_edge_change = 0;  ///< mean over edges of |d_ij - delta_ij| / delta_ij
    double beta = 0;                       ///< beta used
    numerics::LinearSolver linear_solver =
        numerics::LinearSolver::Direct;   ///< solver used (Direct or Multigrid)
    int coarse_levels = 0;                ///< coarser problems solved for SMACOF's start (header note)
    int coarse_iterations = 0;            ///< their SMACOF iterations, all levels (not in `iterations`)
    double seconds = 0;                   ///< wall time of the whole computation
    double conformal_factor_seconds = 0;  ///< of which: the conformal factor
    double setup_seconds = 0;             ///< of which: feature points, pairs, factor / multigrid of V
    double smacof_seconds = 0;            ///< of which: the SMACOF iterations (coarse start included)
};

/// Computes the canonical form of the mesh (V #V x 3, F #F x 3). Throws InputError on bad input
/// (validate_mesh), NumericalError on numerical failure, Cancelled if progress returns false.
EuclideanCanonicalFormResult euclidean_canonical_form(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                      const EuclideanCanonicalFormOptions& options = {});

/// The registry's method euclidean-A or euclidean-N (method_registry.h): its parameters with the
/// variant's defaults, its run, its summary.
CanonicalMethod euclidean_method(CanonicalVariant variant);

/// The SMACOF pairs of step 4 for a scaled mesh V, its edges E (#E x 2), normalised phi and
/// feature points; exposed for tests and for callers that want to run SMACOF themselves.
numerics::StressPairs canonical_form_pairs(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E,
                                           const Eigen::VectorXd& phi, const std::vector<int>& features,
                                           const EuclideanCanonicalFormOptions& options);

}  // namespace canonform::canonical
