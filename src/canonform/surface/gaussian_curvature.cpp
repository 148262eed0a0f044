// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/gaussian_curvature.h"

#include "canonform/common/errors.h"
#include "canonform/numerics/portable_math.h"
#include "canonform/surface/mesh_topology.h"

#include <Eigen/Geometry>

#include <cmath>

namespace canonform::surface {

Eigen::VectorXd gaussian_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                   const std::vector<bool>& known_boundary) {
    if (!known_boundary.empty() && static_cast<Eigen::Index>(known_boundary.size()) != V.rows())
        throw InputError("gaussian_curvature: the boundary flags do not have one entry per vertex");
    const auto boundary =
        known_boundary.empty() ? boundary_vertices(static_cast<int>(V.rows()), F) : known_boundary;
    Eigen::VectorXd K(V.rows());
    for (Eigen::Index v = 0; v < V.rows(); ++v) K(v) = boundary[static_cast<size_t>(v)] ? M_PI : 2 * M_PI;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
            const int k = F(f, c), i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
            const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
            K(k) -= numerics::portable_atan2(a.cross(b).norm(),
                                             a.dot(b));  // not libm: the same bits on every CPU
        }
    }
    return K;
}

}  // namespace canonform::surface
