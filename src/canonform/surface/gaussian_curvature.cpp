// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/gaussian_curvature.h"

#include "canonform/common/errors.h"
#include "canonform/numerics/portable_math.h"
#include "canonform/surface/mesh_topology.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace canonform::surface {

Eigen::VectorXd gaussian_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                   const std::vector<bool>& known_boundary) {
    if (!known_boundary.empty() && static_cast<Eigen::Index>(known_boundary.size()) != V.rows())
        throw InputError("gaussian_curvature: the boundary flags do not have one entry per vertex");
    const auto boundary =
        known_boundary.empty() ? boundary_vertices(static_cast<int>(V.rows()), F) : known_boundary;
    Eigen::VectorXd K(V.rows());
    for (Eigen::Index v = 0; v < V.rows(); ++v) K(v) = boundary[static_cast<size_t>(v)] ? M_PI : 2 * M_PI;
    // The angles of a block of faces at a time (three per face, in order), then subtracted in the
    // same order as one by one: the same bits, with the arctangents four at a time.
    constexpr Eigen::Index kBlock = 512;
    std::vector<double> ys(static_cast<size_t>(3 * kBlock)), xs(ys.size()), angles(ys.size());
    for (Eigen::Index first = 0; first < F.rows(); first += kBlock) {
        const Eigen::Index last = std::min<Eigen::Index>(F.rows(), first + kBlock);
        size_t m = 0;
        for (Eigen::Index f = first; f < last; ++f)
            for (int c = 0; c < 3; ++c, ++m) {
                const int k = F(f, c), i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
                const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
                ys[m] = a.cross(b).norm();
                xs[m] = a.dot(b);
            }
        numerics::portable_atan2(ys.data(), xs.data(), angles.data(),
                                 m);  // not libm: the same bits on every CPU
        m = 0;
        for (Eigen::Index f = first; f < last; ++f)
            for (int c = 0; c < 3; ++c, ++m) K(F(f, c)) -= angles[m];
    }
    return K;
}

}  // namespace canonform::surface
