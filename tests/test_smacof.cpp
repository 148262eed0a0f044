// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/numerics/rigid_alignment.h"
#include "canonform/numerics/smacof.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/mesh_topology.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <random>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::canonical;
using namespace canonform::procedural;

namespace {

Eigen::MatrixXd random_points(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd X(n, 3);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) X(i, c) = u(rng);
    return X;
}

StressPairs all_pairs(const Eigen::MatrixXd& X) {
    StressPairs p;
    for (int i = 0; i < X.rows(); ++i)
        for (int j = i + 1; j < X.rows(); ++j) p.add(i, j, (X.row(i) - X.row(j)).norm(), 1.0);
    return p;
}

/// The sparse weighted pairs of StressNeverIncreases: a mesh's edges with distorted targets and
/// weights plus a few long-range pairs.
StressPairs distorted_pairs(const Mesh& s) {
    StressPairs p;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.5, 2.0);
    for (Eigen::Index f = 0; f < s.F.rows(); ++f)
        for (int c = 0; c < 3; ++c) {
            const int a = s.F(f, c), b = s.F(f, (c + 1) % 3);
            if (a < b) p.add(a, b, u(rng) * (s.V.row(a) - s.V.row(b)).norm(), u(rng));
        }
    for (int k = 0; k < 40; ++k) p.add(k, 300 + k, 3.0, 0.5);
    return p;
}

const SmacofAcceleration kAllAccelerations[] = {SmacofAcceleration::None, SmacofAcceleration::Relaxed,
                                                SmacofAcceleration::Rre, SmacofAcceleration::Mpe,
                                                SmacofAcceleration::Anderson};

}  // namespace

TEST(Smacof, FullWeightRecoversAKnownPointSet) {
    const Eigen::MatrixXd X = random_points(30, 1);
    const SmacofSolver solver(30, all_pairs(X));
    SmacofOptions opt;
    opt.tolerance = 1e-12;
    opt.max_iterations = 5000;
    const SmacofResult r = solver.solve(random_points(30, 2), opt);
    // Distances recovered, and the configuration equals X up to a rigid motion.
    double worst = 0;
    for (int i = 0; i < 30; ++i)
        for (int j = i + 1; j < 30; ++j)
            worst =
                std::max(worst, std::abs((r.X.row(i) - r.X.row(j)).norm() - (X.row(i) - X.row(j)).norm()));
    EXPECT_LT(worst, 1e-4);
    EXPECT_LT(align_rigid(r.X, X).rms, 1e-4);
    EXPECT_LT(r.final_stress, 1e-8 * r.initial_stress);
}

TEST(Smacof, StressNeverIncreases) {
    // Sparse weighted pairs: a mesh's edges with distorted targets plus a few long-range pairs.
    const Mesh s = make_icosphere(3);
    const StressPairs p = distorted_pairs(s);
    const SmacofSolver solver(static_cast<int>(s.V.rows()), p);
    SmacofOptions opt;
    opt.tolerance = 0;
    opt.max_iterations = 200;
    opt.record_history = true;
    opt.acceleration = SmacofAcceleration::None;  // plain Guttman steps (accelerations: below)
    const SmacofResult r = solver.solve(s.V, opt);
    ASSERT_EQ(r.stress_history.size(), 201u);
    for (size_t k = 1; k < r.stress_history.size(); ++k)
        EXPECT_LE(r.stress_history[k], r.stress_history[k - 1] * (1 + 1e-12)) << "iteration " << k;
    EXPECT_LT(r.stress_history.back(), 0.5 * r.stress_history.front());
    EXPECT_NEAR(solver.stress(r.X), r.final_stress, 1e-9 * r.final_stress);
    EXPECT_FALSE(r.converged);
    EXPECT_EQ(r.iterations, 200);
}

TEST(Smacof, GuttmanTransformEqualsPseudoInverseSolution) {
    // Compare with a dense V^+ B(X) X on a small problem.
    const Eigen::MatrixXd X = random_points(12, 4);
    StressPairs p;
    for (int i = 0; i < 12; ++i) p.add(i, (i + 1) % 12, 1.0 + 0.1 * i, 1.0 + i);
    for (int i = 0; i < 6; ++i) p.add(i, i + 6, 2.5, 0.3);
    const SmacofSolver solver(12, p);
    Eigen::MatrixXd Vd = Eigen::MatrixXd::Zero(12, 12), B = Eigen::MatrixXd::Zero(12, 12);
    for (size_t k = 0; k < p.size(); ++k) {
        const int a = p.i[k], b = p.j[k];
        Vd(a, a) += p.w[k];
        Vd(b, b) += p.w[k];
        Vd(a, b) -= p.w[k];
        Vd(b, a) -= p.w[k];
        const double d = (X.row(a) - X.row(b)).norm();
        const double bij = -p.w[k] * p.delta[k] / d;  // eq. (3)
        B(a, b) += bij;
        B(b, a) += bij;
        B(a, a) -= bij;  // eq. (4) with the sign that makes rows sum to zero
        B(b, b) -= bij;
    }
    const Eigen::MatrixXd Vplus = Vd.completeOrthogonalDecomposition().pseudoInverse();
    Eigen::MatrixXd expected = Vplus * B * X;
    expected.rowwise() -= expected.colwise().mean();
    EXPECT_LT((solver.guttman(X) - expected).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Smacof, AGivenOrderingOfVSolvesTheSameSteps) {
    // The canonical form factors V with the conformal factor's ordering (feature points last)
    // instead of AMD's: the Guttman steps must be the same up to rounding.
    const Mesh s = make_icosphere(3);
    const StressPairs p = distorted_pairs(s);
    const int n = static_cast<int>(s.V.rows());
    const SmacofSolver amd(n, p);
    SmacofSolverOptions o;
    o.linear_solver = LinearSolver::Direct;
    o.ordering.resize(static_cast<size_t>(n - 1));
    for (int k = 0; k < n - 1; ++k) o.ordering[static_cast<size_t>(k)] = n - 2 - k;  // reversed
    const SmacofSolver given(n, p, o);
    const Eigen::MatrixXd X = random_points(n, 5);
    EXPECT_LT((given.guttman(X) - amd.guttman(X)).cwiseAbs().maxCoeff(), 1e-10);
    o.ordering.pop_back();  // wrong length: named, not used
    EXPECT_THROW(SmacofSolver(n, p, o), InputError);
}

TEST(Smacof, ThreeDimensionalPointsGiveTheBitsOfTheGeneralLoop) {
    // Three-dimensional points take their own path through B(X) X and the stress (coordinates side
    // by side, four pairs' square roots and divisions at a time): the same operations in the same
    // order as any other dimension's loop, so the same bits as the points with a fourth coordinate
    // of 0 - with a pair count that leaves a remainder of the four, and a pair of coincident points
    // (no term in B(X) X).
    const Mesh s = make_icosphere(3);
    StressPairs p = distorted_pairs(s);
    while (p.size() % 4 != 3) p.add(1, 2 + static_cast<int>(p.size() % 7), 0.7, 1.5);
    const int n = static_cast<int>(s.V.rows());
    const SmacofSolver solver(n, p);
    Eigen::MatrixXd X = random_points(n, 9);
    X.row(300) = X.row(0);  // the pair (0, 300) has d = 0
    Eigen::MatrixXd X4 = Eigen::MatrixXd::Zero(n, 4);
    X4.leftCols(3) = X;
    EXPECT_EQ(solver.stress(X), solver.stress(X4));
    double s3 = 0, s4 = 0;
    const Eigen::MatrixXd Y3 = solver.guttman(X, &s3), Y4 = solver.guttman(X4, &s4);
    EXPECT_EQ(s3, s4);
    ASSERT_EQ(Y3.cols(), 3);
    EXPECT_TRUE(Y3 == Y4.leftCols(3)) << (Y3 - Y4.leftCols(3)).cwiseAbs().maxCoeff();
    EXPECT_GT(s3, 0);
}

TEST(Smacof, RejectsADisconnectedPairGraphAndBadWeights) {
    StressPairs p;
    p.add(0, 1, 1.0, 1.0);
    p.add(2, 3, 1.0, 1.0);
    EXPECT_THROW(SmacofSolver(4, p), InputError);
    StressPairs q;
    q.add(0, 1, 1.0, -1.0);
    EXPECT_THROW(SmacofSolver(2, q), InputError);
    StressPairs r;
    r.add(0, 1, std::nan(""), 1.0);
    EXPECT_THROW(SmacofSolver(2, r), InputError);
}

TEST(Smacof, MultigridStepsNeverRaiseTheStressAndMatchTheDirectSolve) {
    // The inexact Guttman step (one AMG V-cycle from X) keeps the majorisation, and the canonical
    // form it converges to is the direct solver's, within the stopping rule's spread.
    const Figure fig = make_figure(6000, figure_pose(2));
    EuclideanCanonicalFormOptions opt;
    opt.smacof.tolerance = 1e-6;
    opt.smacof.record_history = true;
    opt.linear_solver = LinearSolver::Direct;
    const EuclideanCanonicalFormResult d = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, opt);
    opt.linear_solver = LinearSolver::Multigrid;
    const EuclideanCanonicalFormResult m = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, opt);
    EXPECT_EQ(d.linear_solver, LinearSolver::Direct);
    ASSERT_EQ(m.linear_solver, LinearSolver::Multigrid);
    for (size_t k = 1; k < m.stress_history.size(); ++k)
        EXPECT_LE(m.stress_history[k], m.stress_history[k - 1] * (1 + 1e-12)) << "iteration " << k;
    EXPECT_TRUE(m.converged);
    EXPECT_NEAR(m.final_stress, d.final_stress, 2e-3 * d.final_stress);
    const double diff = test::aligned_rms(m.V, d.V);
    std::printf("[ info ] multigrid vs direct: %d vs %d iterations, stress %.6g vs %.6g, aligned rms %.2e\n",
                m.iterations, d.iterations, m.final_stress, d.final_stress, diff);
    EXPECT_LT(diff, 0.02);
}

TEST(Smacof, ALargeMultigridStepIsCloseToTheDirectOneOnAnyNumberOfThreads) {
    // From 131072 points the step's per-row passes (the translated start, the centring) and the
    // V-cycle's sweeps run on every thread. A grid of 380 x 380 points, its edges with targets
    // off by up to a factor 2: one multigrid step from X lands near the exact step (the V-cycle
    // closes most of the majoriser's gap from the start), centred, the stress goes down, and one
    // thread gives the same bits.
    const int side = 380, n = side * side;
    StressPairs p;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.5, 2.0);
    Eigen::MatrixXd X(n, 3);
    for (int x = 0; x < side; ++x)
        for (int y = 0; y < side; ++y) {
            const int i = x * side + y;
            X.row(i) << x, y, 0.1 * std::sin(0.05 * x * y);
            if (x + 1 < side) p.add(i, i + side, u(rng), 1.0);
            if (y + 1 < side) p.add(i, i + 1, u(rng), 1.0);
        }
    SmacofSolverOptions o;
    o.linear_solver = LinearSolver::Direct;
    const Eigen::MatrixXd exact = SmacofSolver(n, p, o).guttman(X);
    o.linear_solver = LinearSolver::Multigrid;
    const SmacofSolver mg(n, p, o);
    double s0 = 0, s1 = 0;
    const Eigen::MatrixXd Y = mg.guttman(X, &s0);
    mg.guttman(Y, &s1);
    EXPECT_LT(s1, s0);
    // The majorising quadratic the step minimises, sum w |y_a - y_b|^2 - 2 tr(Y^T B(X) X)
    // (translation invariant): the V-cycle closes most of its gap from X to the exact minimum.
    Eigen::MatrixXd BX = Eigen::MatrixXd::Zero(n, 3);
    for (size_t k = 0; k < p.size(); ++k) {
        const Eigen::RowVector3d t = X.row(p.i[k]) - X.row(p.j[k]);
        const double f = p.w[k] * p.delta[k] / t.norm();
        BX.row(p.i[k]) += f * t;
        BX.row(p.j[k]) -= f * t;
    }
    const auto quadratic = [&](const Eigen::MatrixXd& Z) {
        double q = -2 * (Z.array() * BX.array()).sum();
        for (size_t k = 0; k < p.size(); ++k) q += p.w[k] * (Z.row(p.i[k]) - Z.row(p.j[k])).squaredNorm();
        return q;
    };
    const double q_exact = quadratic(exact);
    std::printf("[ info ] one V-cycle leaves %.3f of the majoriser's gap at %d points\n",
                (quadratic(Y) - q_exact) / (quadratic(X) - q_exact), n);
    EXPECT_LT(quadratic(Y) - q_exact, 0.2 * (quadratic(X) - q_exact));
    EXPECT_LT(Y.colwise().mean().cwiseAbs().maxCoeff(), 1e-9 * Y.cwiseAbs().maxCoeff());  // centred
    o.threads = 1;
    const Eigen::MatrixXd Y1 = SmacofSolver(n, p, o).guttman(X);
    ASSERT_EQ(Y1.rows(), Y.rows());
    for (Eigen::Index i = 0; i < Y.size(); ++i) ASSERT_EQ(Y.data()[i], Y1.data()[i]) << "entry " << i;
}

TEST(Smacof, AutoSolverSwitchesToMultigridAtTheThreshold) {
    const Figure fig = make_figure(3000, figure_pose(0));
    StressPairs p;
    const Eigen::MatrixXi E = unique_edges(fig.mesh.F);
    for (Eigen::Index e = 0; e < E.rows(); ++e)
        p.add(E(e, 0), E(e, 1), (fig.mesh.V.row(E(e, 0)) - fig.mesh.V.row(E(e, 1))).norm(), 1.0);
    SmacofSolverOptions so;
    EXPECT_EQ(SmacofSolver(3000, p, so).linear_solver(), LinearSolver::Direct);
    so.multigrid_from = 2000;
    EXPECT_EQ(SmacofSolver(3000, p, so).linear_solver(), LinearSolver::Multigrid);
    so.linear_solver = LinearSolver::Direct;
    EXPECT_EQ(SmacofSolver(3000, p, so).linear_solver(), LinearSolver::Direct);
}

TEST(SmacofAcceleration, NamesParseBothWaysAndBadNamesAreRefused) {
    for (SmacofAcceleration a : kAllAccelerations) EXPECT_EQ(parse_smacof_acceleration(to_string(a)), a);
    EXPECT_EQ(smacof_acceleration_names().size(), 5u);
    try {
        parse_smacof_acceleration("fast");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("none, relaxed, rre, mpe, anderson"), std::string::npos);
    }
    EXPECT_THROW(GuttmanAccelerator(SmacofAcceleration::Rre, 0), InputError);
}

TEST(SmacofAcceleration, StressNeverIncreasesWithAnyMethod) {
    // Every accepted iterate's stress is at most the previous one's (the safeguard), with both
    // linear solvers; every method gets far below the start.
    const Mesh s = make_icosphere(3);
    for (LinearSolver ls : {LinearSolver::Direct, LinearSolver::Multigrid}) {
        SmacofSolverOptions so;
        so.linear_solver = ls;
        const SmacofSolver solver(static_cast<int>(s.V.rows()), distorted_pairs(s), so);
        for (SmacofAcceleration a : kAllAccelerations) {
            SmacofOptions opt;
            opt.tolerance = 0;
            opt.max_iterations = 150;
            opt.record_history = true;
            opt.acceleration = a;
            opt.acceleration_depth = 4;
            const SmacofResult r = solver.solve(s.V, opt);
            SCOPED_TRACE(std::string(to_string(a)) + (ls == LinearSolver::Direct ? " direct" : " multigrid"));
            EXPECT_EQ(r.stress_history.size(), static_cast<size_t>(r.iterations - r.rejections) + 1);
            EXPECT_LE(r.iterations, 150);
            for (size_t k = 1; k < r.stress_history.size(); ++k)
                ASSERT_LE(r.stress_history[k], r.stress_history[k - 1] * (1 + 1e-12)) << "iterate " << k;
            EXPECT_NEAR(solver.stress(r.X), r.final_stress, 1e-9 * r.final_stress);
            EXPECT_LT(r.final_stress, 0.5 * r.initial_stress);
            if (a == SmacofAcceleration::None) {
                EXPECT_EQ(r.extrapolations + r.rejections, 0);
            } else {
                EXPECT_GT(r.extrapolations, 0);
            }
        }
    }
}

TEST(SmacofAcceleration, EveryMethodReachesThePlainStressOnAFigure) {
    // The Euclidean canonical form (variant N) of a 3000-vertex figure: every method stops within
    // 0.2% of the plain run's final stress, and its form differs from the plain one by about as
    // much as the plain one moves when the tolerance is tightened 100x (the stopping rule's own
    // spread); the default (RRE) takes at most 2/3 of the plain Guttman steps.
    const Figure fig = make_figure(3000, figure_pose(2));
    EuclideanCanonicalFormOptions opt;
    opt.smacof.acceleration = SmacofAcceleration::None;
    const EuclideanCanonicalFormResult plain = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, opt);
    ASSERT_TRUE(plain.converged);
    opt.smacof.tolerance = 1e-7;
    const EuclideanCanonicalFormResult tight = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, opt);
    opt.smacof.tolerance = 1e-5;
    const double spread = test::aligned_rms(plain.V, tight.V);
    std::printf("[ info ] plain: %d steps, stress %.6g; tolerance 1e-7: %d steps, stress %.6g, rms %.2e\n",
                plain.iterations, plain.final_stress, tight.iterations, tight.final_stress, spread);
    for (SmacofAcceleration a : kAllAccelerations) {
        opt.smacof.acceleration = a;
        const EuclideanCanonicalFormResult r = euclidean_canonical_form(fig.mesh.V, fig.mesh.F, opt);
        SCOPED_TRACE(to_string(a));
        const double rms = test::aligned_rms(r.V, plain.V);
        std::printf(
            "[ info ] %-8s %4d steps (%d extrapolations, %d rejected), stress %.6g, rms to plain %.2e\n",
            to_string(a), r.iterations, r.extrapolations, r.rejections, r.final_stress, rms);
        EXPECT_TRUE(r.converged);
        EXPECT_LE(r.final_stress, plain.final_stress * 1.002);
        EXPECT_LT(rms, 1.5 * spread + 1e-3);
        if (a == kDefaultSmacofAcceleration) {
            EXPECT_LE(r.iterations, plain.iterations * 2 / 3);
        }
    }
}

TEST(SmacofAcceleration, DeterministicAndTheDefaultIsRre) {
    const Figure fig = make_figure(1500, figure_pose(3));
    EXPECT_EQ(SmacofOptions{}.acceleration, SmacofAcceleration::Rre);
    EXPECT_EQ(EuclideanCanonicalFormOptions{}.smacof.acceleration, SmacofAcceleration::Rre);
    const EuclideanCanonicalFormResult a = euclidean_canonical_form(fig.mesh.V, fig.mesh.F);
    const EuclideanCanonicalFormResult b = euclidean_canonical_form(fig.mesh.V, fig.mesh.F);
    EXPECT_EQ((a.V - b.V).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(a.iterations, b.iterations);
}
