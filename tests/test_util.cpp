#include "test_util.h"

#include "core/rigid_alignment.h"

namespace canonform::test {

double aligned_rms(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    const RigidAlignment al = align_rigid(a, b);
    const double radius = std::sqrt((b.rowwise() - b.colwise().mean()).squaredNorm() / static_cast<double>(b.rows()));
    return al.rms / radius;
}

}  // namespace canonform::test
