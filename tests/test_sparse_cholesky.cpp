// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/errors.h"
#include "canonform/numerics/sparse_cholesky.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/cotan_laplacian.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::procedural;

namespace {

/// The cotangent Laplacian of a disc with vertex 0 pinned (symmetric positive definite), as the
/// conformal factor factors it.
Eigen::SparseMatrix<double> pinned_laplacian(int vertices) {
    const Mesh d = make_disc(vertices);
    const Eigen::SparseMatrix<double> L = cotan_laplacian(d.V, d.F);
    const Eigen::Index n = L.rows();
    return L.bottomRightCorner(n - 1, n - 1);
}

Eigen::MatrixXd random_rhs(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd B(rows, cols);
    for (Eigen::Index k = 0; k < B.size(); ++k) B.data()[k] = u(g);
    return B;
}

}  // namespace

TEST(SparseCholesky, SolvesEveryColumnAndKeepsWorkingAcrossRightHandSideShapes) {
    const Eigen::SparseMatrix<double> A = pinned_laplacian(600);
    SparseCholesky s;
    ASSERT_TRUE(s.compute(A));
    // The solve workspace is kept between calls: 3, then 1, then 3 columns again must all be right.
    for (const int cols : {3, 1, 3, 2}) {
        const Eigen::MatrixXd B = random_rhs(A.rows(), cols, 7u + static_cast<unsigned>(cols));
        const Eigen::MatrixXd X = s.solve(B);
        ASSERT_TRUE(s.ok());
        ASSERT_EQ(X.cols(), cols);
        EXPECT_LT((A * X - B).norm() / B.norm(), 1e-10) << cols << " columns";
    }
}

TEST(SparseCholesky, AColumnSolvedWithOthersIsTheSameBitsAsAlone) {
    const Eigen::SparseMatrix<double> A = pinned_laplacian(600);
    SparseCholesky s;
    ASSERT_TRUE(s.compute(A));
    const Eigen::MatrixXd B = random_rhs(A.rows(), 5, 11);
    for (const int cols : {3, 5}) {
        const Eigen::MatrixXd X = s.solve(B.leftCols(cols));
        ASSERT_TRUE(s.ok());
        for (int c = 0; c < cols; ++c)
            EXPECT_TRUE(s.solve(B.col(c)) == X.col(c)) << cols << " columns, column " << c;
    }
}

// The solve reads L's row indices as 16 bits up to 65536 rows, as 32 bits above: either way three
// columns solved together are the bits of each solved alone (the one-column solve reads 32 bits).
TEST(SparseCholesky, ThreeColumnsAreTheSameBitsEitherSideOfSixteenBitRowIndices) {
    for (const int n : {65536, 65537}) {
        // A path with random weights, a chord every 97 rows (fill in L), and a positive diagonal.
        std::mt19937 g(static_cast<unsigned>(n));
        std::uniform_real_distribution<double> u(0.5, 2.0);
        std::vector<Eigen::Triplet<double>> t;
        Eigen::VectorXd diagonal = Eigen::VectorXd::Constant(n, 1e-3);
        const auto edge = [&](int a, int b) {
            const double w = u(g);
            t.emplace_back(std::max(a, b), std::min(a, b), -w);
            diagonal(a) += w;
            diagonal(b) += w;
        };
        for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
        for (int i = 0; i + 5000 < n; i += 97) edge(i, i + 5000);
        for (int i = 0; i < n; ++i) t.emplace_back(i, i, diagonal(i));
        Eigen::SparseMatrix<double> A(n, n);  // lower triangle, as compute() reads it
        A.setFromTriplets(t.begin(), t.end());
        SparseCholesky s;
        ASSERT_TRUE(s.compute(A)) << n;
        const Eigen::MatrixXd B = random_rhs(n, 3, 13);
        const Eigen::MatrixXd X = s.solve(B);
        ASSERT_TRUE(s.ok()) << n;
        const Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Lower>();
        EXPECT_LT((full * X - B).norm() / B.norm(), 1e-10) << n;
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(s.solve(B.col(c)) == X.col(c)) << n << " rows, column " << c;
    }
}

TEST(SparseCholesky, AGivenOrderingGivesTheSameSolutionAndIsReportedBack) {
    const Eigen::SparseMatrix<double> A = pinned_laplacian(600);
    const Eigen::MatrixXd B = random_rhs(A.rows(), 3, 3);
    SparseCholesky own;
    ASSERT_TRUE(own.compute(A));
    const Eigen::MatrixXd X = own.solve(B);
    const std::vector<int> amd = own.ordering();
    ASSERT_EQ(static_cast<Eigen::Index>(amd.size()), A.rows());
    std::vector<int> sorted = amd;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> identity(amd.size());
    std::iota(identity.begin(), identity.end(), 0);
    EXPECT_EQ(sorted, identity) << "the ordering is a permutation";

    // AMD's own ordering given back: the same factor, the same bits.
    SparseCholesky again;
    ASSERT_TRUE(again.compute(A, amd));
    EXPECT_EQ(again.ordering(), amd);
    EXPECT_TRUE(again.solve(B) == X);

    // Any other permutation (here: reversed) is used as given and solves the same system.
    std::vector<int> reversed(identity.rbegin(), identity.rend());
    SparseCholesky other;
    ASSERT_TRUE(other.compute(A, reversed));
    EXPECT_NE(other.ordering(), amd);
    const Eigen::MatrixXd Y = other.solve(B);
    ASSERT_TRUE(other.ok());
    EXPECT_LT((Y - X).norm() / X.norm(), 1e-10);
}

TEST(SparseCholesky, BadOrderingsAndMatricesAreRefusedNotUsed) {
    const Eigen::SparseMatrix<double> A = pinned_laplacian(300);
    SparseCholesky s;
    EXPECT_THROW(s.compute(A, std::vector<int>{0, 1, 2}), InputError);  // wrong length
    Eigen::SparseMatrix<double> rect(4, 3);
    EXPECT_THROW(s.compute(rect), InputError);
    std::vector<int> twice(static_cast<size_t>(A.rows()), 0);  // not a permutation
    EXPECT_FALSE(s.compute(A, twice));
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(s.solve(Eigen::MatrixXd::Ones(A.rows(), 1)).size(), 0);
    EXPECT_FALSE(s.ok());
    std::vector<int> outside(static_cast<size_t>(A.rows()));
    std::iota(outside.begin(), outside.end(), 1);  // n is no row
    EXPECT_FALSE(s.compute(A, outside));
    // A NaN in the matrix: refused by the factorisation or by the solve, never passed on.
    Eigen::SparseMatrix<double> bad = A;
    bad.valuePtr()[0] = std::nan("");
    SparseCholesky nan_factor;
    if (nan_factor.compute(bad)) {
        nan_factor.solve(Eigen::MatrixXd::Ones(A.rows(), 1));
        EXPECT_FALSE(nan_factor.ok());
    }
}
