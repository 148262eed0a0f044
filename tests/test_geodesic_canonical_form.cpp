// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/procedural/procedural_meshes.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::canonical;
using namespace canonform::procedural;

namespace {

const char* mds_method_name(MdsMethod m) {
    return m == MdsMethod::LeastSquares ? "least squares"
           : m == MdsMethod::Classical  ? "classical"
                                        : "landmark";
}

class EachMds : public ::testing::TestWithParam<MdsMethod> {};

}  // namespace

TEST_P(EachMds, RemovesMostOfThePose) {
    // Like the Euclidean form's test: poses 1 and 3 against the rest pose, at ~600 vertices.
    GeodesicCanonicalFormOptions o;
    o.method = GetParam();
    const Figure p0 = make_figure(600, figure_pose(0));
    const auto c0 = geodesic_canonical_form(p0.mesh.V, p0.mesh.F, o);
    EXPECT_EQ(c0.V.rows(), p0.mesh.V.rows());
    EXPECT_TRUE(c0.V.allFinite());
    EXPECT_GT(c0.geodesic_seconds, 0);
    double mean_ratio = 0;
    for (int pose : {1, 3}) {
        const Figure p = make_figure(600, figure_pose(pose));
        const auto c = geodesic_canonical_form(p.mesh.V, p.mesh.F, o);
        const double ratio =
            test::aligned_rms_or_mirrored(c.V, c0.V) / test::aligned_rms(p.mesh.V, p0.mesh.V);
        std::printf("      %s pose 0-%d: ratio %.2f (%d iterations, %.2f s)\n", mds_method_name(GetParam()),
                    pose, ratio, c.iterations, c.seconds);
        mean_ratio += ratio / 2;
    }
    EXPECT_LT(mean_ratio, 0.5);
}

TEST(GeodesicCanonicalForm, LeastSquaresLowersTheStress) {
    GeodesicCanonicalFormOptions o;
    const Figure f = make_figure(500, figure_pose(2));
    const auto r = geodesic_canonical_form(f.mesh.V, f.mesh.F, o);
    EXPECT_LT(r.final_stress, r.initial_stress);
    EXPECT_GT(r.iterations, 0);
}

INSTANTIATE_TEST_SUITE_P(Methods, EachMds,
                         ::testing::Values(MdsMethod::LeastSquares, MdsMethod::Classical,
                                           MdsMethod::Landmark),
                         [](const auto& param_info) {
                             return std::string(param_info.param == MdsMethod::LeastSquares ? "LS"
                                                : param_info.param == MdsMethod::Classical  ? "C"
                                                                                            : "F");
                         });

TEST(GeodesicCanonicalForm, EstimatesGrowQuadratically) {
    const GeodesicCost a = estimate_geodesic_canonical_form(2000, MdsMethod::LeastSquares, 1);
    const GeodesicCost b = estimate_geodesic_canonical_form(4000, MdsMethod::LeastSquares, 1);
    EXPECT_NEAR(b.bytes / a.bytes, 4.0, 0.2);
    EXPECT_GT(b.seconds / a.seconds, 4.0);  // n^2 log n
    EXPECT_GT(a.bytes, 8.0 * 2000 * 2000);  // at least the distance matrix
    const GeodesicCost f = estimate_geodesic_canonical_form(4000, MdsMethod::Landmark, 1);
    EXPECT_LT(f.bytes, b.bytes);
}

TEST(GeodesicCanonicalForm, RefusesAnOverLargeMeshNamingMemoryAndTime) {
    const Figure f = make_figure(600, figure_pose(0));
    GeodesicCanonicalFormOptions o;
    o.max_memory_gib = 0.001;  // 1 MiB: a 600 x 600 matrix alone needs 2.7 MiB
    try {
        geodesic_canonical_form(f.mesh.V, f.mesh.F, o);
        FAIL() << "not refused";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("GiB"), std::string::npos) << m;
        EXPECT_NE(m.find(" s "), std::string::npos) << m;
        EXPECT_NE(m.find("max_memory_gib"), std::string::npos) << m;
    }
    o.max_memory_gib = 4;
    o.max_seconds = 1e-6;
    EXPECT_THROW(geodesic_canonical_form(f.mesh.V, f.mesh.F, o), InputError);
    o.max_seconds = 600;  // raised limits: it runs
    EXPECT_NO_THROW(geodesic_canonical_form(f.mesh.V, f.mesh.F, o));
    // The default limits refuse 100k vertices (80 GB for the distance matrix alone).
    EXPECT_GT(estimate_geodesic_canonical_form(100000, MdsMethod::LeastSquares).bytes / (1 << 30), 4.0);
}
