// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: late fusion of retrieval distance matrices (a "fused" method of `canonform retrieve`).
//
// Reference: none in Pickup et al. 2015; standard score-level fusion: E. A. Fox and J. A. Shaw,
// "Combination of multiple searches", TREC-2, 1994 (CombSUM: a weighted sum of normalised scores),
// with per-query z-normalisation of the scores (the "Z-norm" of score fusion, e.g. M. Montague and
// J. A. Aslam, "Relevance score normalization for metasearch", CIKM 2001).
//
// Rule `fused:` (FusionRule::RowZScore, the default): every member's N x N distance matrix D_k
// (the same models in the same order) is z-normalised per query (row): for row i, with mu_ki and
// sigma_ki the mean and standard deviation of D_k(i, j) over j != i,
//     Z_k(i, j) = (D_k(i, j) - mu_ki) / sigma_ki        (sigma_ki = 0: divided by 1 instead),
// then F = sum_k w_k Z_k, symmetrised, D(i, j) = (F(i, j) + F(j, i)) / 2, and shifted by one
// constant so that the smallest off-diagonal entry is 0 (the diagonal is 0). A constant changes no
// ranking; the per-query normalisation puts every query's distances of every member on one scale,
// so a member whose distances are spread unevenly over the queries (some queries far from all
// models) weighs as its weight says for every query, and the symmetrisation lets the two queries
// of a pair vote (a pair near in i's ranking but not in j's moves down). On one member the rule
// is a re-ranking of that member (its z-normalised, symmetrised matrix), which is itself better
// than the raw matrix on the collections measured (docs/results.md, "Fused methods").
// Rule `fused-median:` (FusionRule::GlobalMedian, the previous rule): D = sum_k w_k D_k / median_k,
// with median_k the median of D_k's off-diagonal entries (1 instead of a median of 0).
// Default weights (none given): a member `none` (the original meshes) weighs kFusedNoneWeight
// (kFusedMedianNoneWeight for `fused-median:`) and the other members share the rest equally;
// without a `none` member all weigh 1 / members. Given weights are used as written (not
// normalised: the ranking does not depend on a common factor). The rule and the default weight
// were chosen over four collections together - TOSCA, the procedural figures, FAUST and the mixed
// SHREC'07 half - as the largest worst first-tier margin over the better member, averaged over
// codebook seeds 0-2, among five rules and nine weights (tools/fused_defaults.py; docs/design.md,
// "Retrieval defaults"). No rule and weight is at least as good as the better member on all four.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::retrieval {

/// Default weight of a `none` member under the default rule (docs/design.md, "Retrieval defaults").
inline constexpr double kFusedNoneWeight = 0.3;
/// Default weight of a `none` member under `fused-median:` (the previous default).
inline constexpr double kFusedMedianNoneWeight = 0.2;

/// How the members' matrices are put on one scale before the weighted sum (header comment).
enum class FusionRule {
    RowZScore,     ///< `fused:`: per-query z-scores, weighted sum, symmetrised (default)
    GlobalMedian,  ///< `fused-median:`: each matrix divided by its median off-diagonal entry
};

/// A fused method: two or more member methods (as written in --method, e.g. "euclidean-N:beta=65")
/// and their weights.
struct FusedSpec {
    std::vector<std::string> members;  ///< member method specs, in order
    std::vector<double> weights;       ///< one per member (> 0, finite)
    bool default_weights = false;      ///< weights not given (names then carry no weights)
    FusionRule rule = FusionRule::RowZScore;
    /// "fused:none+euclidean-N" (default weights) or "fused-median:none*0.5+euclidean-N*0.5".
    std::string to_string() const;
    /// Folder of its results: "fused_none+euclidean-N" or "fused-median_none0.5+euclidean-N0.5"
    /// (member folders, i.e. MethodSpec::folder(), as `member_folders` gives them, in order).
    std::string folder(const std::vector<std::string>& member_folders) const;
};

/// True if a --method entry is a fused method ("fused:..." or "fused-median:...").
bool is_fused_spec(const std::string& text);

/// Parses "fused:A+B[+C...]" (or "fused-median:...") with optional "*WEIGHT" after each member
/// ("fused:none*0.5+euclidean-N*0.5"). Without any weight the default weights apply (above);
/// weights must be given for all members or none. InputError on fewer than two members, an empty
/// member, a repeated member, or a weight that is not a finite number > 0.
FusedSpec parse_fused_spec(const std::string& text);

/// Median of the off-diagonal entries of a square matrix (N >= 2); InputError otherwise.
double off_diagonal_median(const Eigen::MatrixXf& D);

/// Per-row z-scores of the off-diagonal entries (diagonal 0; a row of equal entries: centred only).
/// InputError unless square of size >= 3 (a row needs two entries for a spread).
Eigen::MatrixXd row_zscores(const Eigen::MatrixXf& D);

/// The fused matrix of `rule` (header comment) from the members' matrices and their weights.
/// InputError if the counts differ, there is no matrix, a weight is not finite, or the matrices are
/// not all square of one size (>= 2 for GlobalMedian, >= 3 for RowZScore).
Eigen::MatrixXf fuse_distances(const std::vector<Eigen::MatrixXf>& D, const std::vector<double>& weights,
                               FusionRule rule = FusionRule::RowZScore);

}  // namespace canonform::retrieval
