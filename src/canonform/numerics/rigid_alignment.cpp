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
    // H = sum a_k b_k^T, summed point by point in a fixed order (an Eigen product would split the
    // sum into blocks sized from the CPU's L1 cache, so its rounding would depend on the CPU).
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    for (Eigen::Index k = 0; k < A.rows(); ++k) H.noalias() += A.row(k).transpose() * B.row(k);
    RigidAlignment r;
    double trace_sd = 0;
    r.R = best_rotation(H, &trace_sd);
    if (with_scale) {
        const double var = A.squaredNorm();
        r.scale = var > 0 ? trace_sd / var : 1.0;
    }
    r.t = cd - r.scale * cs * r.R.transpose();
    r.rms = std::sqrt((apply(r, src) - dst).squaredNorm() / static_cast<double>(src.rows()));
    return r;
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
