// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the geodesic canonical form of Elad and Kimmel, the baseline of Pickup et al.
//
// References: A. Elad and R. Kimmel, "On bending invariant signatures for surfaces", IEEE TPAMI
// 25(10), 2003; Pickup et al., Pattern Recognition 2015, Section 3.1 and Table 1 (methods C, F, LS).
//
// 1. Scale the mesh to unit radius (as the Euclidean method does, so the two are comparable).
// 2. All-pairs geodesic distances by fast marching (geodesic_distances.h): O(N^2 log N) time and
//    N^2 doubles of memory - the cost the paper's method avoids.
// 3. Embed them in R^3 by MDS (mds.h): least squares (SMACOF, all pairs, unit weights, as Elad and
//    Kimmel; "LS"), classical ("C"), or fast (landmark MDS; "F").
//    Least squares starts from the classical MDS configuration: started from the mesh itself,
//    SMACOF keeps pose-dependent local minima (a curled tail stays curled: on our figures the
//    canonical forms of two poses then differed by 0.79 of the poses' own difference, 0.4 from
//    classical MDS).
// 4. Map the result back to the input's units and centroid (like euclidean_canonical_form.h).
//
// Because the cost grows like N^2 (memory) and N^2 log N (time), the computation first estimates
// both from N and refuses, naming the two figures, when they exceed limits the caller can raise.
#pragma once

#include "canonform/canonical/method_registry.h"
#include "canonform/common/errors.h"
#include "canonform/numerics/mds.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>

namespace canonform::canonical {

/// Options of geodesic_canonical_form().
struct GeodesicCanonicalFormOptions {
    numerics::MdsMethod method =
        numerics::MdsMethod::LeastSquares;  ///< step 3: the paper's LS, C and F (landmark MDS)
    /// Step 3's MDS (mds.h): its SMACOF iteration (least squares only), landmarks and seed. Its
    /// dim (3), threads, input check and progress are set from here.
    numerics::MdsOptions mds;
    int threads = 0;              ///< threads for the geodesics and MDS; 0 = all cores
    double max_memory_gib = 4.0;  ///< refuse when the estimate exceeds this (GiB)
    double max_seconds = 600.0;   ///< refuse when the estimated time exceeds this (s)
    bool restore_scale = true;    ///< result in the input's units and position
    ProgressFn progress;          ///< optional progress callback
};

/// The parameters of these options a user sets - tolerance, max_iterations, acceleration (its
/// MDS's), max_memory_gib, max_seconds - with their defaults from `defaults` (common/parameters.h).
ParameterSet<GeodesicCanonicalFormOptions> geodesic_canonical_form_parameters(
    const GeodesicCanonicalFormOptions& defaults = {});

/// Estimated cost of geodesic_canonical_form() for n vertices.
struct GeodesicCost {
    double bytes = 0;    ///< peak memory (dominated by the n x n distance matrix)
    double seconds = 0;  ///< wall time on this machine class with `threads` threads
    /// "about 1.2 GiB and 340 s" - for messages.
    std::string describe() const;
};

/// Cost estimate from the vertex count (calibrated on a 2-core 2026 x86-64 machine; see the .cpp).
GeodesicCost estimate_geodesic_canonical_form(long n, numerics::MdsMethod method, int threads = 0);

/// Result of geodesic_canonical_form(): the form, the MDS run's statistics (SmacofStatistics:
/// SMACOF's for least squares, else the eigen/landmark steps; unit-radius frame) and the timings.
struct GeodesicCanonicalFormResult : numerics::SmacofStatistics {
    Eigen::MatrixXd V;                     ///< canonical form, #V x 3 (same vertex order and faces)
    double mean_relative_edge_change = 0;  ///< mean over edges of |d_ij - |e_ij|| / |e_ij|
    double geodesic_seconds = 0;           ///< wall time of step 2
    double mds_seconds = 0;                ///< wall time of step 3
    double seconds = 0;                    ///< wall time of everything
    GeodesicCost estimate;                 ///< what was estimated beforehand
};

/// The registry's method geodesic-ls, geodesic-classical or geodesic-fast (method_registry.h).
CanonicalMethod geodesic_method(numerics::MdsMethod mds);

/// Computes the geodesic canonical form. Throws InputError on bad input or when the estimated
/// memory or time exceeds the limits (the message names both figures and the option to raise),
/// NumericalError on numerical failure, Cancelled if progress returns false.
GeodesicCanonicalFormResult geodesic_canonical_form(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                    const GeodesicCanonicalFormOptions& options = {});

}  // namespace canonform::canonical
