// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/sparse_columns.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

using namespace canonform;
using namespace canonform::numerics;

TEST(SparseColumns, EntriesStartAtZeroAndSumInCallOrder) {
    ColumnEntries c;
    c.add(5, -0.0);  // 0 + (-0) is +0, as coeffRef()'s new entry gives
    c.add(2, 1e16);
    c.add(2, 1.0);
    c.add(2, -1e16);  // (1e16 + 1) - 1e16 = 0 in call order; 0 in any order would not hold for all
    c.add(7, 1.0);
    c.add(7, 1e16);
    c.add(7, -1e16);  // (1 + 1e16) - 1e16 = 0 as well, but (1e16 - 1e16) + 1 would be 1
    const auto& e = c.sorted();
    ASSERT_EQ(e.size(), 3u);
    EXPECT_EQ(e[0].first, 2);
    EXPECT_EQ(e[1].first, 5);
    EXPECT_EQ(e[2].first, 7);
    EXPECT_FALSE(std::signbit(e[1].second));
    EXPECT_EQ(e[0].second, (0.0 + 1e16 + 1.0) - 1e16);
    EXPECT_EQ(e[2].second, (0.0 + 1.0 + 1e16) - 1e16);
}

TEST(SparseColumns, AssembledAsCoeffRefAddsTermAfterTerm) {
    // 140,000 columns of random terms (wide-ranging magnitudes, so the order of each entry's terms
    // shows in its bits; enough columns to be shared out): assembled on every thread and on one,
    // against coeffRef() term after term.
    const Eigen::Index n = 140000;
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> row(0, static_cast<int>(n) - 1), offset(-3, 3);
    std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-8, 8);
    std::vector<std::vector<std::pair<int, double>>> terms(static_cast<size_t>(n));
    for (Eigen::Index t = 0; t < 6 * n; ++t) {
        const int c = row(rng);
        const int r = std::min<int>(static_cast<int>(n) - 1, std::max(0, c + offset(rng)));
        terms[static_cast<size_t>(c)].emplace_back(r, mantissa(rng) * std::pow(10.0, exponent(rng)));
    }
    Eigen::SparseMatrix<double> expected(n, n);
    for (Eigen::Index c = 0; c < n; ++c)
        for (const auto& [r, x] : terms[static_cast<size_t>(c)]) expected.coeffRef(r, c) += x;
    expected.makeCompressed();
    for (const int threads : {0, 1}) {
        const Eigen::SparseMatrix<double> M =
            assemble_columns(n, n, threads, [&](Eigen::Index c, ColumnEntries& column) {
                for (const auto& [r, x] : terms[static_cast<size_t>(c)]) column.add(r, x);
            });
        ASSERT_EQ(M.nonZeros(), expected.nonZeros()) << "threads " << threads;
        EXPECT_EQ(0, std::memcmp(M.outerIndexPtr(), expected.outerIndexPtr(), sizeof(int) * (n + 1)));
        EXPECT_EQ(0, std::memcmp(M.innerIndexPtr(), expected.innerIndexPtr(), sizeof(int) * M.nonZeros()));
        EXPECT_EQ(0, std::memcmp(M.valuePtr(), expected.valuePtr(), sizeof(double) * M.nonZeros()));
    }
}
