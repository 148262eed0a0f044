// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: best rigid (optionally similarity) alignment of two point sets in correspondence.
//
// Reference: W. Kabsch, "A solution for the best rotation to relate two sets of vectors", Acta
// Cryst. A32, 1976; S. Umeyama, "Least-squares estimation of transformation parameters between two
// point patterns", IEEE TPAMI 13(4), 1991 (scale). Reflections are excluded (det R = +1).
// Used to compare canonical forms, which SMACOF determines only up to a rigid motion.
#pragma once

#include <Eigen/Core>

namespace canonform::numerics {

/// Result of align_rigid(): dst ~ s * src * R^T + t (rows are points).
struct RigidAlignment {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::RowVector3d t = Eigen::RowVector3d::Zero();
    double scale = 1.0;
    double rms = 0.0;  ///< root-mean-square distance after alignment
};

/// Best rotation + translation (+ uniform scale if `with_scale`) mapping src onto dst
/// (both #P x 3, row k of one corresponds to row k of the other).
RigidAlignment align_rigid(const Eigen::MatrixXd& src, const Eigen::MatrixXd& dst, bool with_scale = false);

/// src mapped by the alignment (#P x 3).
Eigen::MatrixXd apply(const RigidAlignment& a, const Eigen::MatrixXd& src);

/// H = sum_k a_k b_k^T of two #P x 3 point sets (rows in correspondence), summed point by point in
/// a fixed order (an Eigen product would split the sum into blocks sized from the CPU's L1 cache,
/// so its rounding would depend on the CPU).
Eigen::Matrix3d cross_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);

/// Kabsch's step alone: for centred point sets with cross-covariance H = sum_k a_k b_k^T, the
/// rotation R (det +1) that minimises sum_k |R a_k - b_k|^2 (align_rigid() is this on the centred
/// sets). `trace_sd`, if given, receives tr(S D), Umeyama's numerator of the scale.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& H, double* trace_sd = nullptr);

}  // namespace canonform::numerics
