// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/errors.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/gaussian_curvature.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/surface/vertex_areas.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace canonform;
using namespace canonform::surface;
using namespace canonform::procedural;

TEST(GaussianCurvature, GaussBonnetOnSphere) {
    const Mesh s = make_icosphere(3);
    EXPECT_NEAR(gaussian_curvature(s.V, s.F).sum(), 4 * M_PI, 1e-9);  // chi = 2
}

TEST(GaussianCurvature, GaussBonnetOnTorus) {
    const Mesh t = make_torus(48, 20, 1.0, 0.35);
    const Eigen::VectorXd K = gaussian_curvature(t.V, t.F);
    EXPECT_NEAR(K.sum(), 0.0, 1e-9);  // chi = 0
    // Positive on the outside, negative on the inside of the ring.
    double outer = 0, inner = 0;
    for (Eigen::Index v = 0; v < t.V.rows(); ++v) (t.V.row(v).head<2>().norm() > 1.0 ? outer : inner) += K(v);
    EXPECT_GT(outer, 0);
    EXPECT_LT(inner, 0);
}

TEST(GaussianCurvature, GaussBonnetWithBoundaryOnDisc) {
    const Mesh d = make_disc(500);
    const Eigen::VectorXd K = gaussian_curvature(d.V, d.F);
    EXPECT_NEAR(K.sum(), 2 * M_PI, 1e-9);  // chi = 1; boundary vertices use pi (eq. 8)
    for (Eigen::Index v = 0; v < d.V.rows(); ++v)
        if (d.V.row(v).head<2>().norm() < 0.9) {
            EXPECT_NEAR(K(v), 0.0, 1e-9) << "flat interior";
        }
}

TEST(GaussianCurvature, FigureHasEulerCharacteristicTwo) {
    const Figure f = make_figure(2000, figure_pose(1));
    EXPECT_NEAR(gaussian_curvature(f.mesh.V, f.mesh.F).sum(), 4 * M_PI, 1e-8);
}

TEST(VertexAreas, SumToSurfaceArea) {
    const Mesh s = make_icosphere(4, 2.0);
    const Eigen::VectorXd A = vertex_areas(s.V, s.F);
    EXPECT_NEAR(A.sum(), 4 * M_PI * 4.0, 0.01 * 4 * M_PI * 4.0);
    EXPECT_GT(A.minCoeff(), 0.0);
    const Mesh d = make_disc(700, 1.0);
    EXPECT_NEAR(vertex_areas(d.V, d.F).sum(), M_PI, 0.02 * M_PI);
}

TEST(GaussianCurvature, KnownBoundaryFlagsGiveTheSameCurvature) {
    // The canonical form passes validate_mesh's boundary flags instead of finding them again.
    const Mesh d = make_disc(500);
    const MeshReport report = validate_mesh(d.V, d.F);
    EXPECT_TRUE(gaussian_curvature(d.V, d.F, report.boundary) == gaussian_curvature(d.V, d.F));
    const Mesh s = make_icosphere(2);
    EXPECT_TRUE(gaussian_curvature(s.V, s.F, validate_mesh(s.V, s.F).boundary) ==
                gaussian_curvature(s.V, s.F));
    EXPECT_THROW(gaussian_curvature(d.V, d.F, std::vector<bool>(3, false)), InputError);
}
