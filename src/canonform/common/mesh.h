// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the one mesh type of the project.
#pragma once

#include <Eigen/Core>

namespace canonform {

/// An indexed triangle mesh: V #V x 3 (double), F #F x 3 (0-based rows of V; empty for a point
/// cloud). Algorithms take V and F as plain matrices; this pairs them where a mesh is passed on.
struct Mesh {
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
};

}  // namespace canonform
