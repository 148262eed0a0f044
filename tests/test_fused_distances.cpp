// Tests of canonform/retrieval/fused_distances.h.
#include "canonform/retrieval/fused_distances.h"

#include <gtest/gtest.h>

using namespace canonform;
using namespace canonform::retrieval;

TEST(FusedDistances, ParsesMembersAndWeights) {
    const FusedSpec a = parse_fused_spec("fused:none+euclidean-N");
    ASSERT_EQ(a.members, (std::vector<std::string>{"none", "euclidean-N"}));
    EXPECT_TRUE(a.default_weights);
    EXPECT_DOUBLE_EQ(a.weights[0], kFusedNoneWeight);  // the original meshes weigh less by default
    EXPECT_DOUBLE_EQ(a.weights[1], 1 - kFusedNoneWeight);
    EXPECT_EQ(a.to_string(), "fused:none+euclidean-N");
    EXPECT_EQ(a.folder({"none", "euclidean-N"}), "fused_none+euclidean-N");
    const FusedSpec e = parse_fused_spec("fused:euclidean-A+euclidean-N+none");
    EXPECT_DOUBLE_EQ(e.weights[0], (1 - kFusedNoneWeight) / 2);
    EXPECT_DOUBLE_EQ(e.weights[2], kFusedNoneWeight);
    const FusedSpec q = parse_fused_spec("fused:euclidean-A+euclidean-N");
    EXPECT_DOUBLE_EQ(q.weights[0], 0.5);
    const FusedSpec h = parse_fused_spec("fused:none*0.5+euclidean-N*0.5");
    EXPECT_FALSE(h.default_weights);
    EXPECT_EQ(h.folder({"none", "euclidean-N"}), "fused_none0.5+euclidean-N0.5");
    const FusedSpec b = parse_fused_spec("fused:none*0.3+euclidean-N:beta=65*0.7+euclidean-A*2");
    ASSERT_EQ(b.members.size(), 3u);
    EXPECT_EQ(b.members[1], "euclidean-N:beta=65");
    EXPECT_DOUBLE_EQ(b.weights[0], 0.3);
    EXPECT_DOUBLE_EQ(b.weights[2], 2.0);
    EXPECT_EQ(b.to_string(), "fused:none*0.3+euclidean-N:beta=65*0.7+euclidean-A*2");
    EXPECT_EQ(b.folder({"none", "euclidean-N_beta65", "euclidean-A"}), "fused_none0.3+euclidean-N_beta650.7+euclidean-A2");
    EXPECT_TRUE(is_fused_spec("fused:a+b"));
    EXPECT_FALSE(is_fused_spec("euclidean-N"));
    for (const char* bad : {"fused:none", "fused:", "fused:none+", "fused:none+none", "fused:none*0.5+euclidean-N",
                            "fused:none*0+euclidean-N*1", "fused:none*-1+euclidean-N*1", "fused:none*x+euclidean-N*1",
                            "fused:none*inf+euclidean-N*1", "none+euclidean-N"})
        EXPECT_THROW(parse_fused_spec(bad), InputError) << bad;
}

TEST(FusedDistances, OffDiagonalMedian) {
    Eigen::MatrixXf D(3, 3);
    D << 100, 1, 2, 3, 100, 4, 5, 6, 100;  // off-diagonal 1..6: median (3 + 4) / 2
    EXPECT_DOUBLE_EQ(off_diagonal_median(D), 3.5);
    Eigen::MatrixXf E(2, 2);
    E << 0, 7, 9, 0;
    EXPECT_DOUBLE_EQ(off_diagonal_median(E), 8.0);
    EXPECT_THROW(off_diagonal_median(Eigen::MatrixXf(1, 1)), InputError);
    EXPECT_THROW(off_diagonal_median(Eigen::MatrixXf(2, 3)), InputError);
}

TEST(FusedDistances, WeightedSumOfMedianNormalisedMatrices) {
    Eigen::MatrixXf A(3, 3), B(3, 3);
    A << 0, 1, 2, 1, 0, 3, 2, 3, 0;           // median 2
    B << 0, 10, 40, 10, 0, 30, 40, 30, 0;     // median 30
    const Eigen::MatrixXf F = fuse_distances({A, B}, {0.25, 0.75});
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(F(i, j), 0.25 * A(i, j) / 2 + 0.75 * B(i, j) / 30, 1e-6);
    // Scale invariance: a member multiplied by a constant gives the same fused matrix.
    const Eigen::MatrixXf G = fuse_distances({A * 1000.f, B}, {0.25, 0.75});
    EXPECT_TRUE(F.isApprox(G, 1e-6f));
    // One member alone keeps its ranking; a zero median divides by 1.
    const Eigen::MatrixXf Z = Eigen::MatrixXf::Zero(3, 3);
    EXPECT_TRUE(fuse_distances({Z, A}, {1, 1}).isApprox(A / 2.f));
    EXPECT_THROW(fuse_distances({A}, {1, 2}), InputError);
    EXPECT_THROW(fuse_distances({}, {}), InputError);
    EXPECT_THROW(fuse_distances({A, Eigen::MatrixXf::Zero(4, 4)}, {1, 1}), InputError);
}
