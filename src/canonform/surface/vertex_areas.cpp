// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/vertex_areas.h"

#include <Eigen/Geometry>

namespace canonform::surface {

Eigen::VectorXd vertex_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    Eigen::VectorXd A = Eigen::VectorXd::Zero(V.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d a = V.row(F(f, 1)) - V.row(F(f, 0)), b = V.row(F(f, 2)) - V.row(F(f, 0));
        const double third = a.cross(b).norm() / 6.0;
        for (int c = 0; c < 3; ++c) A(F(f, c)) += third;
    }
    return A;
}

}  // namespace canonform::surface
