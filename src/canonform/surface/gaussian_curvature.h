// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: discrete Gaussian curvature by angle deficit.
//
// Reference: Pickup et al., Pattern Recognition 2015, eq. (8) (after Ben-Chen and Gotsman,
// "Characterizing shape using conformal factors", 3DOR 2008):
//   K0_v = 2 pi - sum of the corner angles at v       (interior vertex)
//   K0_v =   pi - sum of the corner angles at v       (boundary vertex)
// This is integrated curvature (radians, scale invariant); it satisfies the discrete
// Gauss-Bonnet theorem: sum_v K0_v = 2 pi chi(M), with or without boundary.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace canonform::surface {

/// Angle-deficit Gaussian curvature per vertex (#V); boundary vertices use pi (eq. 8).
/// `boundary` (#V flags, e.g. MeshReport::boundary of validate_mesh) if known, else found from F.
/// `threads` (0: every core) share the work on large meshes; the values do not depend on them.
Eigen::VectorXd gaussian_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                   const std::vector<bool>& boundary = {}, int threads = 0);

}  // namespace canonform::surface
