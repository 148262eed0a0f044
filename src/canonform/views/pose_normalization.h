// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: pose normalisation for the view-based descriptor of Lian et al. (CM-BOF): PCA and
// rectilinearity, keeping the better of the two.
//
// References: Z. Lian, P. L. Rosin, X. Sun, "Rectilinearity of 3D meshes", IJCV 89(2-3), 2010
// (the rectilinearity pose and the PCA/rectilinearity combination); Z. Lian, A. Godil, X. Sun,
// J. Xiao, "CM-BOF", Machine Vision and Applications 2013; Pickup et al., Pattern Recognition 2015,
// Section 3 ("normalised using a combination of PCA and rectilinearity").
//
// Steps (X = the normalised vertices, one row per vertex):
// 1. Centre on the vertex mean c; scale by s = 1 / max_i |v_i - c| (largest radius becomes 1).
// 2. PCA candidate: eigenvectors of the vertex covariance (1/n) sum (v - c)(v - c)^T, largest
//    eigenvalue first.
// 3. Rectilinearity candidate: starting from the PCA frame, minimise over rotations Q
//        P(Q) = sum_t |Q a_t|_1 / sum_t |a_t|,   a_t = area vector of triangle t (area x unit normal),
//    i.e. the sum of the areas of the projections of all triangles on the yz, xz and xy planes,
//    divided by the surface area (P in [1, sqrt 3]; Lian et al.'s rectilinearity is a decreasing
//    function of the minimum of P: 1 for a box-like mesh). Around each start Q_k a rotation is
//    parametrised by a vector x as R(x) Q_k, R(x) = the rotation of the quaternion (1, x/2) (angle
//    2 atan(|x|/2), so about |x| for small x; only +, -, *, /, no libm). Start 0 is the PCA frame,
//    starts 1..restarts-1 are random rotations of it (std::mt19937_64 seeded with `seed`, raw
//    64-bit outputs, so platform independent). Each start runs up to 3 Nelder-Mead rounds
//    (initial steps 0.3, 0.06, 0.012) until a round does not improve; the lowest P over all starts
//    wins. Its axes are canonicalised (step 4) and it is refined on every face by 5 Nelder-Mead
//    rounds (initial steps 0.3 * 0.2^r, r = 0..4), always all 5: P has many shallow local minima
//    close together, and a rule "stop when a round does not improve" was decided by rounding.
//    Departure (for speed): the starts' coarse search minimises P over the area vectors summed per
//    direction bin (PoseOptions::direction_bins; equal to P when no bin holds vectors whose
//    rotated components differ in sign), only the refinement uses every face.
// 4. Axis canonicalisation (both candidates): P is invariant under the 24 cube rotations, and PCA
//    axes have free signs, so each candidate frame is made unique by (a) ordering its axes by the
//    second moment of X along them, largest first, then (b) choosing signs: of the three axes, the
//    two with the largest |third moment| get a positive third moment, and the sign of the
//    remaining one makes det R = +1. (For a mirror-symmetric shape the third moment across the
//    symmetry plane is ~0, so it is the axis left to the determinant.)
// 5. Selection (our reading of Lian et al. 2010's "simple selection criterion"): keep the
//    candidate whose axis-aligned bounding box of X has the smaller volume; PCA wins ties.
//    pca_cost and rect_cost are these volumes.
//
// Invariance: the result is equivariant under rigid motions and uniform scaling of the input
// (tested to 1e-6 on X) unless the shape is degenerate for one of the rules: two (nearly) equal PCA
// eigenvalues or second moments, two axes with (nearly) zero third moment, two distinct local
// minima of P with (nearly) equal value, or (nearly) equal bounding-box volumes.
// The same on every x86-64 CPU, to the bit: only +, -, *, /, sqrt and comparisons, in an order
// fixed at compile time. No libm function (sin, cos, atan, exp, log, pow have FMA variants chosen
// at run time), and no Eigen matrix product with a long inner dimension (Eigen splits it into
// blocks sized from the L1 cache that CPUID reports, so the rounding depends on the CPU): the
// covariance is summed row by row.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstdint>

namespace canonform::views {

/// Options of normalize_pose().
struct PoseOptions {
    int restarts = 8;        ///< rectilinearity starts (>= 1): the PCA frame + restarts-1 random
    std::uint64_t seed = 0;  ///< seed of the random starts
    /// The coarse search of every start runs on the area vectors summed per direction bin (a cube
    /// map of 6 x bins x bins cells, in the PCA frame); the winner is then refined on every face.
    /// 0 = every face throughout (slower; docs/benchmarks.md, "View descriptor", has both timings).
    int direction_bins = 16;
};

/// A similarity transform to the normalised pose (see apply_pose for the convention).
struct PoseNormalization {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();         ///< rotation (det +1); rows = the new x, y,
                                                             ///< z axes in input coordinates
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();  ///< vertex mean of the input
    double scale = 1.0;                ///< 1 / largest distance of a vertex from the centre
    double pca_cost = 0.0;             ///< selection criterion of the PCA pose: AABB volume
    double rect_cost = 0.0;            ///< selection criterion of the rectilinearity pose: AABB volume
    double pca_projected_area = 0.0;   ///< P (projected area / surface area) of the PCA pose
    double rect_projected_area = 0.0;  ///< P of the rectilinearity pose (<= pca_projected_area)
    bool used_rectilinearity = false;  ///< R is the rectilinearity pose (else the PCA pose)
};

/// Computes the normalising pose of the mesh (V: #V x 3, F: #F x 3, 0-based). Throws InputError
/// for no faces, fewer than 3 vertices, non-finite coordinates, out-of-range indices, all vertices
/// at one point, or zero surface area; InputError if restarts < 1.
PoseNormalization normalize_pose(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const PoseOptions& options = {});

/// Applies the pose: each row v becomes (R (s (v - c)^T))^T, i.e.
/// X = ((V - 1 c) * scale) * R^T. The result has its vertex mean at the origin and lies in the
/// closed unit ball.
Eigen::MatrixXd apply_pose(const PoseNormalization& pose, const Eigen::MatrixXd& V);

/// P(R) of step 3: sum over faces of |R a_t|_1 divided by the surface area, for the mesh as given
/// (no centring/scaling needed: P is scale and translation invariant). Throws InputError for zero
/// area.
double projected_area_ratio(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity());

}  // namespace canonform::views
