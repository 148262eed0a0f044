// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: barycentric vertex areas.
//
// Reference: Pickup et al., Pattern Recognition 2015, eq. (9): the area attached to a vertex is
// one third of the area of its incident triangles, sum_{t in T_v} Area(t) / 3. The areas sum to
// the total surface area.
#pragma once

#include <Eigen/Core>

namespace canonform::surface {

/// Barycentric vertex area: one third of the one-ring area (#V), in squared units of V.
Eigen::VectorXd vertex_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace canonform::surface
