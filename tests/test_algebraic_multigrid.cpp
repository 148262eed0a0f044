// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/numerics/algebraic_multigrid.h"
#include "canonform/numerics/sparse_cholesky.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_topology.h"

#include <gtest/gtest.h>

#include <random>

#if defined(CANONFORM_HAVE_TBB)
#include <tbb/global_control.h>
#endif

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::canonical;
using namespace canonform::procedural;

namespace {

// SMACOF's V (variant N) of a procedural figure with vertex 0 pinned: the matrix the solver sees.
Eigen::SparseMatrix<double> figure_v(int vertices) {
    const Figure fig = make_figure(vertices, figure_pose(1));
    const Eigen::MatrixXd V = normalize_scale(fig.mesh.V);
    const ConformalFactorResult cf = conformal_factor(V, fig.mesh.F);
    const Eigen::MatrixXi E = unique_edges(fig.mesh.F);
    const FeaturePoints fp =
        feature_points(vertex_adjacency(static_cast<int>(V.rows()), E), cf.normalized, {});
    const StressPairs p = canonical_form_pairs(V, E, cf.normalized, fp.indices, {});
    const int n = static_cast<int>(V.rows());
    std::vector<Eigen::Triplet<double>> t;
    for (size_t k = 0; k < p.size(); ++k) {
        const int a = p.i[k], b = p.j[k];
        if (a > 0) t.emplace_back(a - 1, a - 1, p.w[k]);
        if (b > 0) t.emplace_back(b - 1, b - 1, p.w[k]);
        if (a > 0 && b > 0) {
            t.emplace_back(a - 1, b - 1, -p.w[k]);
            t.emplace_back(b - 1, a - 1, -p.w[k]);
        }
    }
    Eigen::SparseMatrix<double> A(n - 1, n - 1);
    A.setFromTriplets(t.begin(), t.end());
    return A;
}

Eigen::MatrixXd random_block(Eigen::Index n, int k, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    Eigen::MatrixXd B(n, k);
    for (Eigen::Index i = 0; i < n; ++i)
        for (int c = 0; c < k; ++c) B(i, c) = g(rng);
    return B;
}

// The 5-point Laplacian of a side x side grid plus a small multiple of the identity (SPD): 1.25M
// non-zeros at side 500, so its Gauss-Seidel sweeps and products run on every hardware thread.
Eigen::SparseMatrix<double> grid_laplacian(int side) {
    std::vector<Eigen::Triplet<double>> t;
    const auto id = [side](int x, int y) { return x * side + y; };
    for (int x = 0; x < side; ++x)
        for (int y = 0; y < side; ++y) {
            double d = 1e-3;
            for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                const int u = x + dx, v = y + dy;
                if (u < 0 || v < 0 || u >= side || v >= side) continue;
                t.emplace_back(id(x, y), id(u, v), -1.0);
                d += 1;
            }
            t.emplace_back(id(x, y), id(x, y), d);
        }
    Eigen::SparseMatrix<double> A(side * side, side * side);
    A.setFromTriplets(t.begin(), t.end());
    return A;
}

double energy(const Eigen::SparseMatrix<double>& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& X) {
    return 0.5 * (X.transpose() * (A * X)).trace() - (X.transpose() * B).trace();
}

}  // namespace

TEST(AlgebraicMultigrid, PcgMatchesTheDirectSolve) {
    const Eigen::SparseMatrix<double> A = figure_v(6000);
    const AmgPreconditioner amg(A);
    EXPECT_GE(amg.num_levels(), 2);
    EXPECT_LT(amg.operator_complexity(), 2.0);
    const Eigen::MatrixXd B = random_block(A.rows(), 3, 1);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(A.rows(), 3);
    const PcgReport rep = amg.pcg(B, X, 1e-10, 200);
    ASSERT_TRUE(rep.converged);
    EXPECT_LE(rep.relative_residual, 1e-10);
    SparseCholesky direct;
    ASSERT_TRUE(direct.compute(A));
    const Eigen::MatrixXd Xd = direct.solve(B);
    EXPECT_LT((X - Xd).norm() / Xd.norm(), 1e-7);
}

TEST(AlgebraicMultigrid, CgStepsDoNotGrowWithTheMesh) {
    // The point of multigrid: the number of preconditioned CG steps to a fixed residual
    // reduction stays about the same as the mesh is refined (here 4x).
    int steps[2];
    const int sizes[2] = {4000, 16000};
    for (int s = 0; s < 2; ++s) {
        const Eigen::SparseMatrix<double> A = figure_v(sizes[s]);
        const AmgPreconditioner amg(A);
        Eigen::MatrixXd X = Eigen::MatrixXd::Zero(A.rows(), 3);
        const PcgReport rep = amg.pcg(random_block(A.rows(), 3, 2), X, 1e-8, 500);
        ASSERT_TRUE(rep.converged);
        steps[s] = rep.iterations;
    }
    std::printf("[ info ] AMG-PCG steps to 1e-8: %d at 4000, %d at 16000 vertices\n", steps[0], steps[1]);
    EXPECT_LE(steps[1], steps[0] + 5);
    EXPECT_LE(steps[1], 40);
}

TEST(AlgebraicMultigrid, VCyclesNeverRaiseTheEnergyAndConverge) {
    const Eigen::SparseMatrix<double> A = figure_v(5000);
    const AmgPreconditioner amg(A);
    const Eigen::MatrixXd B = random_block(A.rows(), 3, 3);
    Eigen::MatrixXd X = random_block(A.rows(), 3, 4);
    SparseCholesky direct;
    ASSERT_TRUE(direct.compute(A));
    const Eigen::MatrixXd Xd = direct.solve(B);
    const double e_star = energy(A, B, Xd);
    double e = energy(A, B, X);
    const double gap0 = e - e_star;
    for (int c = 0; c < 12; ++c) {
        amg.cycle(B, X, 1);
        const double e1 = energy(A, B, X);
        EXPECT_LE(e1, e + 1e-9 * std::abs(e)) << "cycle " << c;
        e = e1;
    }
    // Twelve cycles cut the energy gap by orders of magnitude.
    EXPECT_LT(e - e_star, 1e-4 * gap0);
}

TEST(AlgebraicMultigrid, ColumnsAreIndependent) {
    // Solving two right-hand sides together equals solving each alone.
    const Eigen::SparseMatrix<double> A = figure_v(3000);
    const AmgPreconditioner amg(A);
    const Eigen::MatrixXd B = random_block(A.rows(), 2, 5);
    Eigen::MatrixXd X2 = Eigen::MatrixXd::Zero(A.rows(), 2);
    amg.cycle(B, X2, 3);
    for (int c = 0; c < 2; ++c) {
        Eigen::MatrixXd X1 = Eigen::MatrixXd::Zero(A.rows(), 1);
        amg.cycle(B.col(c), X1, 3);
        EXPECT_LT((X1.col(0) - X2.col(c)).norm(), 1e-12 * (1 + X1.norm()));
    }
}

TEST(AlgebraicMultigrid, AWorkspaceKeptBetweenCyclesGivesTheSameBits) {
    // SMACOF keeps one workspace for all its steps (no allocations per step); reusing it, also
    // across a change of the number of columns, must not change a single bit of any result.
    const Eigen::SparseMatrix<double> A = figure_v(3000);
    const AmgPreconditioner amg(A);
    AmgPreconditioner::Workspace work;
    for (int round = 0; round < 4; ++round) {
        const int k = round == 2 ? 1 : 3;
        const Eigen::MatrixXd B = random_block(A.rows(), k, 10 + static_cast<unsigned>(round));
        Eigen::MatrixXd fresh = random_block(A.rows(), k, 20 + static_cast<unsigned>(round));
        Eigen::MatrixXd reused = fresh;
        amg.cycle(B, fresh, 2);
        amg.cycle(B, reused, 2, work);
        ASSERT_EQ(fresh.rows(), reused.rows());
        for (Eigen::Index i = 0; i < fresh.size(); ++i)
            ASSERT_EQ(fresh.data()[i], reused.data()[i]) << "round " << round;
    }
}

TEST(AlgebraicMultigrid, ALargeSystemSharedOverThreadsStillConvergesLikeGaussSeidel) {
    // From 1M non-zeros a level's sweeps run its row chunks colour by colour on every thread:
    // Gauss-Seidel in another fixed order of the rows, so each cycle still lowers the energy, the
    // cycles converge, and the bits do not depend on how many threads there are (nor do those of
    // the set-up's products, shared the same way).
    const Eigen::SparseMatrix<double> A = grid_laplacian(500);
    ASSERT_GE(A.nonZeros(), 1000000);
    const AmgPreconditioner amg(A);
    const Eigen::MatrixXd B = random_block(A.rows(), 3, 30);
    const Eigen::MatrixXd X0 = random_block(A.rows(), 3, 31);
    Eigen::MatrixXd X = X0;
    double e = energy(A, B, X);
    for (int c = 0; c < 6; ++c) {
        amg.cycle(B, X, 1);
        const double e1 = energy(A, B, X);
        EXPECT_LT(e1, e) << "cycle " << c;
        e = e1;
    }
    Eigen::MatrixXd Xp = Eigen::MatrixXd::Zero(A.rows(), 3);
    const PcgReport rep = amg.pcg(B, Xp, 1e-8, 100);
    EXPECT_TRUE(rep.converged);
    EXPECT_LE(rep.iterations, 40);
#if defined(CANONFORM_HAVE_TBB)
    Eigen::MatrixXd X1 = X0;
    {
        // Set up (its sparse products, on every thread above) and cycled on one thread.
        const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        const AmgPreconditioner amg1(A);
        for (int c = 0; c < 6; ++c) amg1.cycle(B, X1, 1);
    }
    ASSERT_EQ(X1.rows(), X.rows());
    for (Eigen::Index i = 0; i < X.size(); ++i) ASSERT_EQ(X.data()[i], X1.data()[i]) << "entry " << i;
#endif
}

TEST(AlgebraicMultigrid, RejectsANonPositiveDiagonal) {
    Eigen::SparseMatrix<double> A(3, 3);
    A.insert(0, 0) = 1;
    A.insert(1, 1) = 0;
    A.insert(2, 2) = 1;
    EXPECT_THROW(AmgPreconditioner{A}, NumericalError);
    Eigen::SparseMatrix<double> B(2, 3);
    EXPECT_THROW(AmgPreconditioner{B}, InputError);
}

TEST(AlgebraicMultigrid, ARowWithOnlyWeakCouplingsIsSolvedToo) {
    // A path of 2,000 vertices (weight 1), vertex 0 pinned, where every third vertex also has a
    // heavy leaf (weight 1e6): the vertices between two heavy ones see only neighbours with far
    // larger diagonals, so all their couplings are weak and their lumped row sums to 0. (SMACOF's
    // V and the conformal factor's Laplacian of irregular meshes have such rows; the AMG threw
    // "non-positive diagonal" on them.) The hierarchy is built and CG with it converges.
    const int path = 2000;
    std::vector<Eigen::Triplet<double>> t;
    const auto edge = [&t](int a, int b, double w) {
        t.emplace_back(a, a, w);
        t.emplace_back(b, b, w);
        t.emplace_back(a, b, -w);
        t.emplace_back(b, a, -w);
    };
    int n = path;
    for (int v = 0; v + 1 < path; ++v) edge(v, v + 1, 1.0);
    for (int v = 0; v < path; v += 3) edge(v, n++, 1e6);
    Eigen::SparseMatrix<double> L(n, n);
    L.setFromTriplets(t.begin(), t.end());
    const Eigen::SparseMatrix<double> A = L.bottomRightCorner(n - 1, n - 1);  // vertex 0 pinned
    AmgOptions o;
    o.coarse_size = 50;
    const AmgPreconditioner amg(A, o);
    EXPECT_GE(amg.num_levels(), 2);
    const Eigen::MatrixXd B = random_block(A.rows(), 1, 3);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(A.rows(), 1);
    const PcgReport rep = amg.pcg(B, X, 1e-10, 500);
    EXPECT_TRUE(rep.converged) << rep.iterations << " steps, residual " << rep.relative_residual;
    EXPECT_TRUE(X.allFinite());
}
