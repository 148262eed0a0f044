// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <set>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::procedural;

namespace {

/// Path graph 0-1-2-...-(n-1).
VertexAdjacency path_graph(int n) {
    Eigen::MatrixXi E(n - 1, 2);
    for (int k = 0; k + 1 < n; ++k) E.row(k) << k, k + 1;
    return vertex_adjacency(n, E);
}

}  // namespace

TEST(FeaturePoints, SqrtCount) {
    EXPECT_EQ(sqrt_count(1), 1);
    EXPECT_EQ(sqrt_count(9), 3);
    EXPECT_EQ(sqrt_count(10), 4);
    EXPECT_EQ(sqrt_count(10000), 100);
    EXPECT_EQ(sqrt_count(10001), 101);
}

TEST(FeaturePoints, RingSizeDecidesWhatIsALocalMaximum) {
    //            0    1    2    3    4    5    6    7
    Eigen::VectorXd phi(8);
    phi << 0.0, 0.5, 0.1, 0.6, 0.2, 0.3, 1.0, 0.9;
    const VertexAdjacency g = path_graph(8);
    EXPECT_EQ(local_maxima(g, phi, 1), (std::vector<int>{1, 3, 6}));
    EXPECT_EQ(local_maxima(g, phi, 2), (std::vector<int>{3, 6}));  // 1 sees 3 at distance 2
    EXPECT_EQ(local_maxima(g, phi, 3), (std::vector<int>{6}));     // 3 sees 6 at distance 3
}

TEST(FeaturePoints, PlateauIsNotAStrictMaximum) {
    Eigen::VectorXd phi(5);
    phi << 0.0, 1.0, 1.0, 0.0, 0.5;
    EXPECT_EQ(local_maxima(path_graph(5), phi, 1), (std::vector<int>{4}));
}

TEST(FeaturePoints, KeepsTheLargestAndFillsRandomlyToExactlySqrtN) {
    // 20 vertices on a path: target ceil(sqrt(20)) = 5.
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(20);
    for (int k = 0; k < 20; ++k) phi(k) = (k % 4 == 1) ? 0.1 * k : 0.001 * k;  // maxima at 1, 5, 9, 13, 17
    const VertexAdjacency g = path_graph(20);
    FeaturePointOptions opt;
    opt.ring = 1;
    opt.count = 3;
    FeaturePoints fp = feature_points(g, phi, opt);
    EXPECT_EQ(fp.indices, (std::vector<int>{17, 13, 9}));
    EXPECT_EQ(fp.total_maxima, 6);  // 1, 5, 9, 13, 17 and the end vertex 19
    opt.count = 21;                 // more than the 20 vertices: refused, not silently cut to 20
    EXPECT_THROW(feature_points(g, phi, opt), InputError);
    opt.count = 20;
    EXPECT_EQ(feature_points(g, phi, opt).indices.size(), 6u);  // all maxima (no fill asked for)

    // Only two maxima with ring 2 on a coarser pattern, then random fill to 5.
    Eigen::VectorXd psi = Eigen::VectorXd::LinSpaced(20, 0.0, 0.19);
    psi(3) = 5.0;  // a peak; the other maximum is the end vertex 19
    opt.count = -1;
    opt.ring = 2;
    opt.fill = FeatureFill::Random;
    opt.seed = 42;
    fp = feature_points(g, psi, opt);
    ASSERT_EQ(fp.indices.size(), 5u);
    EXPECT_EQ(fp.num_maxima, 2);
    EXPECT_EQ(fp.num_random, 3);
    EXPECT_EQ(fp.indices[0], 3);
    EXPECT_EQ(fp.indices[1], 19);
    EXPECT_EQ(std::set<int>(fp.indices.begin(), fp.indices.end()).size(), 5u) << "no duplicates";
    // Same seed, same choice; another seed, (here) another choice.
    EXPECT_EQ(feature_points(g, psi, opt).indices, fp.indices);
    opt.seed = 7;
    EXPECT_NE(feature_points(g, psi, opt).indices, fp.indices);
}

TEST(FeaturePoints, EveryLimbTipOfAFigureIsAFeaturePoint) {
    for (int pose : {0, 1, 3}) {
        const Figure f = make_figure(3000, figure_pose(pose));
        const ConformalFactorResult cf = conformal_factor(f.mesh.V, f.mesh.F);
        const FeaturePoints fp = feature_points(f.mesh.F, cf.normalized, {});
        EXPECT_LE(static_cast<int>(fp.indices.size()), sqrt_count(static_cast<int>(f.mesh.V.rows())));
        for (size_t t = 0; t < f.limb_tips.size(); ++t) {
            double best = 1e30;
            for (int v : fp.indices)
                best = std::min(best, (f.mesh.V.row(v) - f.limb_tips[t].transpose()).norm());
            EXPECT_LT(best, 1.5 * f.limb_radius[t]) << "pose " << pose << ": " << f.limb_names[t];
        }
    }
}

TEST(FeaturePoints, RandomFillIsIndependentOfVertexOrder) {
    const Figure f = make_figure(2000, figure_pose(0));
    const ConformalFactorResult cf = conformal_factor(f.mesh.V, f.mesh.F);
    FeaturePointOptions opt;
    opt.fill = FeatureFill::Random;
    opt.seed = 3;
    const FeaturePoints a = feature_points(f.mesh.F, cf.normalized, opt);

    Eigen::MatrixXd V = f.mesh.V;
    Eigen::MatrixXi F = f.mesh.F;
    const Eigen::VectorXi perm = test::random_permutation(V.rows(), 11);
    test::permute_mesh(perm, V, F);
    const ConformalFactorResult cf2 = conformal_factor(V, F);
    const FeaturePoints b = feature_points(F, cf2.normalized, opt);
    ASSERT_EQ(a.indices.size(), b.indices.size());
    std::set<int> sa(a.indices.begin(), a.indices.end()), sb;
    for (int v : b.indices) sb.insert(perm(v));  // back to the original numbering
    EXPECT_EQ(sa, sb);
}
