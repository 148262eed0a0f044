// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/rigid_alignment.h"
#include "test_util.h"

#include <gtest/gtest.h>

using namespace canonform;
using namespace canonform::numerics;

TEST(RigidAlignment, RecoversAKnownMotion) {
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(50, 3);
    const Eigen::Matrix3d R = test::random_rotation(2);
    const Eigen::MatrixXd B = ((A * R.transpose()).rowwise() + Eigen::RowVector3d(1, 2, 3));
    const RigidAlignment al = align_rigid(A, B);
    EXPECT_LT((al.R - R).norm(), 1e-10);
    EXPECT_LT(al.rms, 1e-10);
    EXPECT_NEAR(al.R.determinant(), 1.0, 1e-12);
    const RigidAlignment sc = align_rigid(A, 2.0 * B, true);
    EXPECT_NEAR(sc.scale, 2.0, 1e-10);
    EXPECT_LT(sc.rms, 1e-9);
}

TEST(RigidAlignment, NeverReflects) {
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(40, 3);
    Eigen::MatrixXd B = A;
    B.col(0) *= -1;  // a mirror image: the best rotation cannot reach it
    const RigidAlignment al = align_rigid(A, B);
    EXPECT_NEAR(al.R.determinant(), 1.0, 1e-12);
    EXPECT_GT(al.rms, 0.1);
}
