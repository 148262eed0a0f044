// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/cotan_laplacian.h"
#include "canonform/surface/gaussian_curvature.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::procedural;

TEST(ConformalFactor, SolvesEquationSevenWithTheDocumentedSign) {
    const Figure f = make_figure(2000, figure_pose(0));
    const ConformalFactorResult cf = conformal_factor(f.mesh.V, f.mesh.F);
    const Eigen::SparseMatrix<double> L = cotan_laplacian(f.mesh.V, f.mesh.F);
    // (D - W) phi = K0 - KT, i.e. eq. (7) with L = W - D.
    const Eigen::VectorXd r = L * cf.raw - (cf.curvature - cf.target);
    EXPECT_LT(r.lpNorm<Eigen::Infinity>(),
              1e-8 * (cf.curvature - cf.target).lpNorm<Eigen::Infinity>() + 1e-12);
    EXPECT_NEAR(cf.curvature.sum(), cf.target.sum(), 1e-9);
    EXPECT_LT(cf.residual, 1e-8);
    EXPECT_NEAR(cf.normalized.minCoeff(), 0.0, 1e-12);
    EXPECT_NEAR(cf.normalized.maxCoeff(), 1.0, 1e-12);
}

TEST(ConformalFactor, NearlyConstantOnASphere) {
    const Mesh s = make_icosphere(4);
    const ConformalFactorResult cf = conformal_factor(s.V, s.F);
    const double sphere_range = cf.raw.maxCoeff() - cf.raw.minCoeff();
    const Figure f = make_figure(2000, figure_pose(0));
    const ConformalFactorResult cff = conformal_factor(f.mesh.V, f.mesh.F);
    const double figure_range = cff.raw.maxCoeff() - cff.raw.minCoeff();
    EXPECT_LT(sphere_range, 0.02) << "a sphere is already conformal to a sphere";
    EXPECT_LT(sphere_range, 0.01 * figure_range);
}

TEST(ConformalFactor, LargestAtTheLimbTips) {
    const Figure f = make_figure(3000, figure_pose(0));
    const ConformalFactorResult cf = conformal_factor(f.mesh.V, f.mesh.F);
    // The tips of the thin limbs lie in the top 10% of the conformal factor (Figs. 3, 4); the
    // round head, a blob rather than a protrusion, above the median.
    std::vector<double> sorted(cf.normalized.data(), cf.normalized.data() + cf.normalized.size());
    std::sort(sorted.begin(), sorted.end());
    const double p90 = sorted[static_cast<size_t>(0.9 * static_cast<double>(sorted.size()))];
    const double p50 = sorted[sorted.size() / 2];
    for (size_t t = 0; t < f.limb_tips.size(); ++t) {
        Eigen::Index nearest;
        (f.mesh.V.rowwise() - f.limb_tips[t].transpose()).rowwise().squaredNorm().minCoeff(&nearest);
        EXPECT_GT(cf.normalized(nearest), f.limb_names[t] == "head" ? p50 : p90) << f.limb_names[t];
    }
}

TEST(ConformalFactor, InvariantToRigidMotionScaleAndPose) {
    const Figure f = make_figure(2000, figure_pose(0));
    const ConformalFactorResult a = conformal_factor(f.mesh.V, f.mesh.F);
    const Eigen::MatrixXd V2 =
        ((3.7 * f.mesh.V * test::random_rotation(5).transpose()).rowwise() + Eigen::RowVector3d(10, -4, 2));
    const ConformalFactorResult b = conformal_factor(V2, f.mesh.F);
    EXPECT_LT((a.raw - b.raw).lpNorm<Eigen::Infinity>(), 1e-8);
    // Another pose: nearly isometric, so nearly the same conformal factor.
    const Figure g = make_figure(2000, figure_pose(3));
    const ConformalFactorResult c = conformal_factor(g.mesh.V, g.mesh.F);
    const double rel = (a.normalized - c.normalized).norm() / a.normalized.norm();
    EXPECT_LT(rel, 0.1);
}

TEST(ConformalFactor, HandlesBoundaries) {
    const Mesh d = make_disc(600);
    const ConformalFactorResult cf = conformal_factor(d.V, d.F);
    EXPECT_TRUE(cf.raw.allFinite());
    EXPECT_LT(cf.residual, 1e-8);
}

TEST(ConformalFactor, RejectsBadInput) {
    const Mesh s = make_icosphere(1);
    Eigen::MatrixXd V = s.V;
    V(3, 1) = std::nan("");
    EXPECT_THROW(conformal_factor(V, s.F), InputError);
    EXPECT_THROW(conformal_factor(s.V, Eigen::MatrixXi(0, 3)), InputError);
}

TEST(ConformalFactor, MultigridSolveEqualsTheDirectOne) {
    // The AMG-preconditioned CG path (used from kMultigridFrom vertices) gives the factorisation's
    // phi; checked here on a smaller mesh by asking for it explicitly.
    const Figure f = make_figure(6000, figure_pose(3));
    ConformalFactorOptions o;
    o.linear_solver = LinearSolver::Direct;
    const ConformalFactorResult d = conformal_factor(f.mesh.V, f.mesh.F, o);
    o.linear_solver = LinearSolver::Multigrid;
    const ConformalFactorResult m = conformal_factor(f.mesh.V, f.mesh.F, o);
    EXPECT_LT((m.raw - d.raw).lpNorm<Eigen::Infinity>(), 1e-7 * d.raw.lpNorm<Eigen::Infinity>());
    EXPECT_LT(m.residual, 1e-8);
    EXPECT_EQ(use_multigrid(LinearSolver::Auto, kMultigridFrom - 1), false);
    EXPECT_EQ(use_multigrid(LinearSolver::Auto, kMultigridFrom), true);
}
