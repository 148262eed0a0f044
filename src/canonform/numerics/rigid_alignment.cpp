// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/rigid_alignment.h"

#include "canonform/common/errors.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace canonform::numerics {

RigidAlignment align_rigid(const Eigen::MatrixXd& src, const Eigen::MatrixXd& dst, bool with_scale) {
    if (src.rows() != dst.rows() || src.cols() != 3 || dst.cols() != 3 || src.rows() == 0)
        throw InputError("rigid alignment needs two non-empty #P x 3 point sets of the same size");
    const Eigen::RowVector3d cs = src.colwise().mean(), cd = dst.colwise().mean();
    const Eigen::MatrixXd A = src.rowwise() - cs, B = dst.rowwise() - cd;
    RigidAlignment r;
    double trace_sd = 0;
    r.R = best_rotation(cross_covariance(A, B), &trace_sd);
    if (with_scale) {
        const double var = A.squaredNorm();
        r.scale = var > 0 ? trace_sd / var : 1.0;
    }
    r.t = cd - r.scale * cs * r.R.transpose();
    r.rms = std::sqrt((apply(r, src) - dst).squaredNorm() / static_cast<double>(src.rows()));
    return r;
}

Eigen::Matrix3d cross_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
    const Eigen::Index n = A.rows();
    const double *a0 = A.col(0).data(), *a1 = A.col(1).data(), *a2 = A.col(2).data();
    const double *b0 = B.col(0).data(), *b1 = B.col(1).data(), *b2 = B.col(2).data();
    double h[3][3] = {};
    for (Eigen::Index k = 0; k < n; ++k) {
        const double a[3] = {a0[k], a1[k], a2[k]}, b[3] = {b0[k], b1[k], b2[k]};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) h[i][j] += a[i] * b[j];
    }
    Eigen::Matrix3d H;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) H(i, j) = h[i][j];
    return H;
}

Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& H, double* trace_sd) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(2, 2) = -1;
    if (trace_sd) *trace_sd = (svd.singularValues().asDiagonal() * D).trace();
    return svd.matrixV() * D * svd.matrixU().transpose();
}

Eigen::MatrixXd apply(const RigidAlignment& a, const Eigen::MatrixXd& src) {
    return ((a.scale * src * a.R.transpose()).rowwise() + a.t);
}

}  // namespace canonform::numerics
