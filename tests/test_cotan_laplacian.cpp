// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/cotan_laplacian.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

using namespace canonform;
using namespace canonform::surface;
using namespace canonform::procedural;

namespace {

void expect_laplacian_properties(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    const Eigen::SparseMatrix<double> L = cotan_laplacian(V, F);
    ASSERT_EQ(L.rows(), V.rows());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(V.rows());
    EXPECT_LT((L * ones).lpNorm<Eigen::Infinity>(), 1e-10) << "L 1 = 0";
    const Eigen::SparseMatrix<double> Lt = L.transpose();
    EXPECT_LT((L - Lt).norm(), 1e-12 * L.norm()) << "L symmetric";
    // Positive semi-definite on these well-shaped meshes: u^T L u >= 0 for random u.
    Eigen::VectorXd u = Eigen::VectorXd::Random(V.rows());
    EXPECT_GE(u.dot(L * u), 0.0);
}

}  // namespace

TEST(CotanLaplacian, SingleEquilateralTriangleWeights) {
    Eigen::MatrixXd V(3, 3);
    V << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0;
    Eigen::MatrixXi F(1, 3);
    F << 0, 1, 2;
    const Eigen::MatrixXd L = Eigen::MatrixXd(cotan_laplacian(V, F));
    const double w = 0.5 / std::tan(M_PI / 3);  // cot(60 deg) / 2
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(L(i, j), i == j ? 2 * w : -w, 1e-12);
}

TEST(CotanLaplacian, RightTriangleHasZeroWeightOppositeTheRightAngle) {
    Eigen::MatrixXd V(3, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    Eigen::MatrixXi F(1, 3);
    F << 0, 1, 2;
    const Eigen::MatrixXd L = Eigen::MatrixXd(cotan_laplacian(V, F));
    EXPECT_NEAR(L(1, 2), 0.0, 1e-12);   // opposite the right angle at vertex 0
    EXPECT_NEAR(L(0, 1), -0.5, 1e-12);  // cot(45 deg) / 2
}

TEST(CotanLaplacian, PropertiesOnSphereTorusDiscAndFigure) {
    const Mesh s = make_icosphere(3);
    expect_laplacian_properties(s.V, s.F);
    const Mesh t = make_torus(40, 16);
    expect_laplacian_properties(t.V, t.F);
    const Mesh d = make_disc(600);
    expect_laplacian_properties(d.V, d.F);
    const Figure f = make_figure(2000, figure_pose(2));
    expect_laplacian_properties(f.mesh.V, f.mesh.F);
}

TEST(CotanLaplacian, ReproducesLinearFunctionsInTheInteriorOfAFlatDisc) {
    // For a flat mesh, (L x)_i = 0 at interior vertices for any linear function x.
    const Mesh d = make_disc(800);
    const Eigen::SparseMatrix<double> L = cotan_laplacian(d.V, d.F);
    const Eigen::VectorXd f = 2 * d.V.col(0) - 3 * d.V.col(1);
    const Eigen::VectorXd Lf = L * f;
    int interior = 0;
    for (Eigen::Index v = 0; v < d.V.rows(); ++v) {
        if (d.V.row(v).head<2>().norm() < 0.9) {
            EXPECT_NEAR(Lf(v), 0.0, 1e-10);
            ++interior;
        }
    }
    EXPECT_GT(interior, 100);
}

TEST(CotanLaplacian, InPlaceAssemblyEqualsTheTripletAssemblyToTheBit) {
    // cotan_laplacian() assembles without a triplet list (memory at 1M vertices); the reference
    // here is the triplet assembly it replaced, summed by setFromTriplets() in the same order.
    const Figure fig = make_figure(3000, figure_pose(3));
    const Eigen::MatrixXd& V = fig.mesh.V;
    const Eigen::MatrixXi& F = fig.mesh.F;
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
            const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3), k = F(f, c);
            const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
            const double w = 0.5 * a.dot(b) / a.cross(b).norm();
            t.emplace_back(i, j, -w);
            t.emplace_back(j, i, -w);
            t.emplace_back(i, i, w);
            t.emplace_back(j, j, w);
        }
    }
    Eigen::SparseMatrix<double> ref(V.rows(), V.rows());
    ref.setFromTriplets(t.begin(), t.end());
    const Eigen::SparseMatrix<double> L = cotan_laplacian(V, F);
    ASSERT_TRUE(L.isCompressed());
    ASSERT_EQ(L.nonZeros(), ref.nonZeros());
    for (Eigen::Index c = 0; c <= L.cols(); ++c) ASSERT_EQ(L.outerIndexPtr()[c], ref.outerIndexPtr()[c]);
    for (Eigen::Index p = 0; p < L.nonZeros(); ++p) {
        ASSERT_EQ(L.innerIndexPtr()[p], ref.innerIndexPtr()[p]);
        ASSERT_EQ(L.valuePtr()[p], ref.valuePtr()[p]) << "entry " << p;
    }
}
