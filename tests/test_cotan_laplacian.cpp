#include "canonform/surface/cotan_laplacian.h"
#include "canonform/procedural/procedural_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace canonform;

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
