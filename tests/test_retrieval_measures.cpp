// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/retrieval_measures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

using namespace canonform;
using namespace canonform::retrieval;

namespace {

// Five models, classes A A A B B; row 0 ranks 3(B) 2(A) 1(A) 4(B).
Eigen::MatrixXd five() {
    Eigen::MatrixXd D(5, 5);
    D << 0.0, 0.5, 0.3, 0.1, 0.9,  //
        0.5, 0.0, 0.2, 0.8, 0.7,   //
        0.3, 0.2, 0.0, 0.6, 0.4,   //
        0.1, 0.8, 0.6, 0.0, 0.05,  //
        0.9, 0.7, 0.4, 0.05, 0.0;
    return D;
}
const std::vector<std::string> kLabels = {"A", "A", "A", "B", "B"};

}  // namespace

TEST(RetrievalMeasures, HandComputedQuery) {
    const Measures m = query_measures(five().row(0).transpose(), kLabels, 0);
    EXPECT_EQ(m.nn, 0.0);
    EXPECT_DOUBLE_EQ(m.first_tier, 0.5);                            // [B A] of C-1 = 2
    EXPECT_DOUBLE_EQ(m.second_tier, 1.0);                           // [B A A B]
    EXPECT_NEAR(m.e_measure, 2.0 / 3.0, 1e-12);                     // K = min(32, N-1) = 4: P = 1/2, R = 1
    EXPECT_NEAR(m.dcg, (1.0 + 1.0 / std::log2(3.0)) / 2.0, 1e-12);  // rel 0 1 1 0; ideal 1 + 1
}

TEST(RetrievalMeasures, TiesAreBrokenByModelIndex) {
    Eigen::VectorXd d(4);
    d << 0.0, 0.2, 0.2, 0.2;
    const std::vector<std::string> labels = {"A", "B", "A", "A"};
    const Measures m = query_measures(d, labels, 0);
    EXPECT_EQ(m.nn, 0.0);  // model 1 (class B) comes first among the tied
    EXPECT_DOUBLE_EQ(m.first_tier, 0.5);
    const std::vector<std::string> swapped = {"A", "A", "B", "A"};
    EXPECT_EQ(query_measures(d, swapped, 0).nn, 1.0);
}

TEST(RetrievalMeasures, SmallClassesAreLeftOutAndAveragesAreMicroAndMacro) {
    const Evaluation e = evaluate(five(), kLabels);
    EXPECT_EQ(e.micro.queries, 3);  // class B (two models) is left out
    ASSERT_EQ(e.skipped_classes.size(), 1u);
    EXPECT_EQ(e.skipped_classes[0], "B");
    ASSERT_EQ(e.classes.size(), 1u);
    // Rows 1 and 2: model 1 ranks 2(A) 0(A) ...: NN 1, FT 1; model 2 ranks 1(A) 0(A) ...: NN 1, FT 1.
    EXPECT_NEAR(e.micro.nn, 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(e.micro.first_tier, (0.5 + 1 + 1) / 3.0, 1e-12);
    EXPECT_NEAR(e.macro.nn, e.micro.nn, 1e-12);  // one class: macro = micro

    // A class of one model in a larger set, N < 33: K = N - 1.
    Eigen::MatrixXd D = Eigen::MatrixXd::Constant(4, 4, 1.0);
    D.diagonal().setZero();
    D(0, 1) = D(1, 0) = 0.1;
    const Evaluation f = evaluate(D, {"A", "A", "A", "C"});
    EXPECT_EQ(f.micro.queries, 3);
    EXPECT_EQ(f.skipped_classes, std::vector<std::string>{"C"});
}

TEST(RetrievalMeasures, PrecisionRecallInterpolatesBetweenHits) {
    const Evaluation e = evaluate(five(), kLabels);
    ASSERT_EQ(e.recall.size(), 20u);
    EXPECT_NEAR(e.recall.front(), 0.05, 1e-12);
    EXPECT_NEAR(e.recall.back(), 1.0, 1e-12);
    // Query 0: hits at ranks 2 and 3 -> (0.5, 1/2), (1, 2/3); queries 1 and 2: ranks 1 and 2 -> (0.5, 1), (1,
    // 1).
    EXPECT_NEAR(e.precision[9], (0.5 + 1 + 1) / 3.0, 1e-12);                         // recall 0.50
    EXPECT_NEAR(e.precision[14], (0.5 + 0.5 * (2.0 / 3.0 - 0.5) + 2) / 3.0, 1e-12);  // recall 0.75
    EXPECT_NEAR(e.precision[19], (2.0 / 3.0 + 2) / 3.0, 1e-12);                      // recall 1.0
}

TEST(RetrievalMeasures, PerfectRetrievalScoresOne) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Constant(6, 6, 1.0);
    const std::vector<std::string> labels = {"a", "a", "a", "b", "b", "b"};
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) D(i, j) = i == j ? 0 : (labels[i] == labels[j] ? 0.1 : 1.0);
    const Evaluation e = evaluate(D, labels);
    EXPECT_DOUBLE_EQ(e.micro.nn, 1);
    EXPECT_DOUBLE_EQ(e.micro.first_tier, 1);
    EXPECT_DOUBLE_EQ(e.micro.second_tier, 1);
    EXPECT_DOUBLE_EQ(e.micro.dcg, 1);
    EXPECT_NEAR(e.micro.e_measure, 2.0 / (1.0 / (2.0 / 5.0) + 1.0), 1e-12);  // K = 5, P = 2/5, R = 1
    for (double p : e.precision) EXPECT_DOUBLE_EQ(p, 1.0);
}

TEST(RetrievalMeasures, RejectsBadInput) {
    EXPECT_THROW(evaluate(Eigen::MatrixXd::Zero(3, 4), {"a", "a", "a"}), InputError);
    EXPECT_THROW(evaluate(Eigen::MatrixXd::Zero(3, 3), {"a", "a"}), InputError);
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(3, 3);
    D(0, 1) = std::nan("");
    EXPECT_THROW(evaluate(D, {"a", "a", "a"}), InputError);
    EXPECT_THROW(evaluate(Eigen::MatrixXd::Zero(3, 3), {"a", "b", "c"}), InputError);  // nothing to evaluate
}

TEST(RetrievalMeasures, NeighbourListsGiveTheMatrixMeasuresAndABoundedTruncatedDcg) {
    // 95 models in classes of 5 to 19 (K = 38) and two too small, distances with many ties.
    std::mt19937_64 g(3);
    std::vector<std::string> labels;
    for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 5 + (c * 7) % 16; ++k) labels.push_back("c" + std::to_string(c));
    labels.push_back("single");
    labels.push_back("pair");
    labels.push_back("pair");
    const int n = static_cast<int>(labels.size());
    Eigen::MatrixXd D(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = i; j < n; ++j) {
            const double same = labels[static_cast<size_t>(i)] == labels[static_cast<size_t>(j)] ? 0.0 : 3.0;
            D(i, j) = D(j, i) = i == j ? 0.0 : same + static_cast<double>(g() % 20);  // few values: ties
        }
    const Evaluation full = evaluate(D, labels);
    const int k = neighbours_needed(labels);
    int largest = 0;
    for (const auto& l : labels)
        largest = std::max<int>(largest, static_cast<int>(std::count(labels.begin(), labels.end(), l)));
    EXPECT_EQ(k, std::max(2 * largest, 32));
    // Each model's first K others in ranking order (ties by index), as the index gives them.
    std::vector<std::vector<std::uint32_t>> lists(static_cast<size_t>(n));
    for (int q = 0; q < n; ++q) {
        std::vector<std::uint32_t> order;
        for (int j = 0; j < n; ++j)
            if (j != q) order.push_back(static_cast<std::uint32_t>(j));
        std::stable_sort(order.begin(), order.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return D(q, a) < D(q, b); });
        order.resize(static_cast<size_t>(k));
        lists[static_cast<size_t>(q)] = order;
    }
    const NeighbourEvaluation e = evaluate_neighbours(lists, labels, k);
    for (const auto& [got, want] :
         {std::pair{e.evaluation.micro, full.micro}, std::pair{e.evaluation.macro, full.macro}}) {
        EXPECT_EQ(got.nn, want.nn);
        EXPECT_EQ(got.first_tier, want.first_tier);
        EXPECT_EQ(got.second_tier, want.second_tier);
        EXPECT_EQ(got.e_measure, want.e_measure);
        EXPECT_EQ(got.queries, want.queries);
        EXPECT_LE(got.dcg, want.dcg);
    }
    EXPECT_LE(full.micro.dcg, e.evaluation.micro.dcg + e.dcg_bound.dcg + 1e-12);
    EXPECT_LE(full.macro.dcg, e.evaluation.macro.dcg + e.dcg_bound_macro + 1e-12);
    EXPECT_GT(e.dcg_bound.dcg, 0.0);  // truncation is real here: some relevant models lie beyond K
    EXPECT_EQ(e.evaluation.classes, full.classes);
    EXPECT_EQ(e.evaluation.skipped_classes, full.skipped_classes);
    EXPECT_TRUE(e.evaluation.precision.empty());
    // Lists of every other model give the matrix's DCG too.
    std::vector<std::vector<std::uint32_t>> whole(static_cast<size_t>(n));
    for (int q = 0; q < n; ++q) {
        for (int j = 0; j < n; ++j)
            if (j != q) whole[static_cast<size_t>(q)].push_back(static_cast<std::uint32_t>(j));
        std::stable_sort(whole[static_cast<size_t>(q)].begin(), whole[static_cast<size_t>(q)].end(),
                         [&](std::uint32_t a, std::uint32_t b) { return D(q, a) < D(q, b); });
    }
    EXPECT_EQ(evaluate_neighbours(whole, labels, n - 1).evaluation.micro.dcg, full.micro.dcg);
    // Too short, the query itself, out of range.
    EXPECT_THROW(evaluate_neighbours(lists, labels, 2 * (largest - 1) - 1), InputError);
    auto bad = lists;
    bad[4][0] = 4;
    EXPECT_THROW(evaluate_neighbours(bad, labels, k), InputError);
    bad[4][0] = static_cast<std::uint32_t>(n);
    EXPECT_THROW(evaluate_neighbours(bad, labels, k), InputError);
    bad = lists;
    bad[7].pop_back();
    EXPECT_THROW(evaluate_neighbours(bad, labels, k), InputError);
}
