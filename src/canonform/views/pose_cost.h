// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the rectilinearity objective's sum (private to the views library; the pose
// normalisation it serves is documented in pose_normalization.h).
#pragma once

#include <Eigen/Core>

namespace canonform::views {
namespace detail {

/// sum over i < n of e_i = (|(q00 x_i + q01 y_i) + q02 z_i| + |(q10 x_i + ...) + q12 z_i|) +
/// |(q20 x_i + ...) + q22 z_i|, every e_i in that order, summed as four running sums of the i
/// with one remainder mod 4 (the first term assigned), combined as (s0 + s2) + (s1 + s3) with a
/// last pair and a last odd term added after, as described in pose_normalization.cpp. That is the
/// order Eigen's sum() of the same array expression takes in packets of two doubles (SSE2, the
/// x86-64 baseline), so the pose keeps its bits; here it is fixed in the source, and the AVX2 and
/// AVX-512 clones evaluate 4 or 8 e_i at a time in the same order.
double rectilinearity_sum(const double* x, const double* y, const double* z, Eigen::Index n,
                          const Eigen::Matrix3d& Q);

}  // namespace detail
}  // namespace canonform::views
