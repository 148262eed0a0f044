#include "test_util.h"

#include "canonform/numerics/rigid_alignment.h"

namespace canonform::test {

double aligned_rms(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    const RigidAlignment al = align_rigid(a, b);
    const double radius = std::sqrt((b.rowwise() - b.colwise().mean()).squaredNorm() / static_cast<double>(b.rows()));
    return al.rms / radius;
}

double aligned_rms_or_mirrored(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd m = a;
    m.col(0) *= -1;
    return std::min(aligned_rms(a, b), aligned_rms(m, b));
}

}  // namespace canonform::test
