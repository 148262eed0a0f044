// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: shape-retrieval measures of a distance matrix, as the Princeton Shape Benchmark's
// psbTable computes them (the measures of Pickup et al. 2015, Tables 2-5 and Figs. 10, 11, 13).
//
// Reference: P. Shilane, P. Min, M. Kazhdan, T. Funkhouser, "The Princeton Shape Benchmark",
// SMI 2004, and its psbTable tool; the definitions the code follows:
// - each query ranks all other models by ascending distance, ties by model index; C = its class size;
// - NN: the first result is of the query's class;
// - first tier: same-class results among the first C-1, divided by C-1;
// - second tier: same-class results among the first 2(C-1), divided by C-1;
// - E-measure: over the first K = min(32, N-1) results, P = hits/K, R = hits/(C-1),
//   E = 2 / (1/P + 1/R), 0 without a hit;
// - DCG: G_1 = rel_1, G_i = G_{i-1} + rel_i / log2(i), divided by the ideal DCG (all C-1 relevant
//   results first);
// - averages: micro (over queries, the default) and macro (over classes); queries of classes with
//   two models or fewer are left out of both.
// - precision-recall: at recall 0.05, 0.10, ..., 1.0; a query's curve passes through its hits
//   (k/(C-1), k/rank_k); precision at a recall level is interpolated linearly between the hits
//   around it, and equals the first hit's precision below it; averaged over queries.
// We normalise by C-1 (psbTable), not by C (the SHREC'16 evaluator): the two must not be mixed.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::retrieval {

/// The five measures (each in [0, 1]).
struct Measures {
    double nn = 0, first_tier = 0, second_tier = 0, e_measure = 0, dcg = 0;
    int queries = 0;  ///< queries averaged
};

/// Measures of a whole evaluation.
struct Evaluation {
    Measures micro;                            ///< mean over queries
    Measures macro;                            ///< mean over classes of the class means
    std::vector<std::string> classes;          ///< class names (evaluated classes only), sorted
    std::vector<Measures> per_class;           ///< same order as `classes`
    std::vector<double> recall;                ///< 0.05, 0.10, ..., 1.0
    std::vector<double> precision;             ///< averaged over queries, same size as recall
    std::vector<std::string> skipped_classes;  ///< classes of one or two models (not averaged)
};

/// The measures as a JSON object ({"nn": ..., "first_tier": ..., ..., "queries": ...}).
nlohmann::ordered_json to_json(const Measures& m);

/// Measures of one query, given its row of distances and the class labels (the query itself,
/// `query`, is excluded from the ranking).
Measures query_measures(const Eigen::VectorXd& distances, const std::vector<std::string>& labels, int query);

/// Evaluates the N x N distance matrix D against labels (N). InputError on a non-square matrix,
/// a label count that differs, or non-finite distances.
Evaluation evaluate(const Eigen::MatrixXd& D, const std::vector<std::string>& labels);

/// Measures of one query from the head of its ranking: rel[i] says whether result i + 1 is of the
/// query's class, c1 = its class size - 1, n = the collection's size. NN, the tiers and the
/// E-measure are those of the whole ranking when rel holds at least max(2 c1, min(32, n - 1))
/// results; DCG counts the results given (truncated when rel is shorter than n - 1).
Measures ranked_measures(const std::vector<char>& rel, int c1, int n);

/// The evaluation from each model's K nearest other models instead of the N x N matrix (the
/// measures above; no precision-recall curve): neighbours[q] = the first results of query q in
/// ranking order (ties by model index, q itself left out), at least min(K, N - 1) each with
/// K >= max(2 (C - 1), 32) for the largest class C. NN, first and second tier and E-measure are
/// then exactly the matrix's; DCG is truncated at K: the full DCG lies in [dcg, dcg + bound],
/// bound (micro and macro in `dcg_bound`) from the relevant models missing from the K (each at a
/// rank above K, weight at most 1 / log2(K + 1)). InputError on lists too short, an index out of
/// range or a label count that differs.
struct NeighbourEvaluation {
    Evaluation evaluation;
    int k = 0;           ///< results per query used
    Measures dcg_bound;  ///< only dcg (micro in `evaluation`'s order) is set
    double dcg_bound_macro = 0;
};
NeighbourEvaluation evaluate_neighbours(const std::vector<std::vector<std::uint32_t>>& neighbours,
                                        const std::vector<std::string>& labels, int k);

/// K for evaluate_neighbours(): max(2 x the largest class, 32), at most N - 1.
int neighbours_needed(const std::vector<std::string>& labels);

}  // namespace canonform::retrieval
