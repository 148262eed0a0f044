// canonform: late fusion of retrieval distance matrices (a "fused" method of `canonform retrieve`).
//
// Reference: none in Pickup et al. 2015; a standard score-level fusion (e.g. E. A. Fox and
// J. A. Shaw, "Combination of multiple searches", TREC-2, 1994: CombSUM over normalised scores).
// The distance matrix of a fused method is
//     D = sum_k w_k * D_k / median_k,
// where D_k is member k's N x N distance matrix (the same models, in the same order) and median_k
// the median of its off-diagonal entries (so members of different scales weigh as their weights
// say; a member whose median is 0, e.g. all models identical under it, is divided by 1 instead).
// Default weights (none given): a member `none` (the original meshes) weighs kFusedNoneWeight and
// the other members share the rest equally; without a `none` member all weigh 1 / members. Given
// weights are used as written (not normalised: the ranking does not depend on a common factor).
// The default was chosen by a sweep on TOSCA, FAUST and the procedural collection (README,
// "Fused methods").
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::retrieval {

/// Default weight of a `none` member (README, "Fused methods": the sweep).
inline constexpr double kFusedNoneWeight = 0.2;

/// A fused method: two or more member methods (as written in --method, e.g. "euclidean-N:beta=65")
/// and their weights.
struct FusedSpec {
    std::vector<std::string> members;  ///< member method specs, in order
    std::vector<double> weights;       ///< one per member (> 0, finite)
    bool default_weights = false;      ///< weights not given (names then carry no weights)
    /// "fused:none+euclidean-N" (default weights) or "fused:none*0.5+euclidean-N*0.5".
    std::string to_string() const;
    /// Folder of its results: "fused_none+euclidean-N" or "fused_none0.5+euclidean-N0.5" (member
    /// folders, i.e. MethodSpec::folder(), as `member_folders` gives them, in order).
    std::string folder(const std::vector<std::string>& member_folders) const;
};

/// True if a --method entry is a fused method ("fused:...").
bool is_fused_spec(const std::string& text);

/// Parses "fused:A+B[+C...]" with optional "*WEIGHT" after each member ("fused:none*0.5+euclidean-N*0.5").
/// Without any weight the default weights apply (above); weights must be given for all members or
/// none. InputError on fewer than two members, an empty member, a repeated member, or a weight
/// that is not a finite number > 0.
FusedSpec parse_fused_spec(const std::string& text);

/// Median of the off-diagonal entries of a square matrix (N >= 2); InputError otherwise.
double off_diagonal_median(const Eigen::MatrixXf& D);

/// sum_k weights[k] * D[k] / off_diagonal_median(D[k]) (1 instead of a median of 0). InputError if
/// the counts differ, there is no matrix, or the matrices are not all square of one size >= 2.
Eigen::MatrixXf fuse_distances(const std::vector<Eigen::MatrixXf>& D, const std::vector<double>& weights);

}  // namespace canonform::retrieval
