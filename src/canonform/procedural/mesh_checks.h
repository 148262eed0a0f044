// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: checks of an extracted figure mesh: closed genus-0 2-manifold, triangle quality
// (private to procedural/).
#pragma once

#include "canonform/procedural/body_model.h"

#include <string>
#include <vector>

namespace canonform::procedural {
namespace detail {

/// Checks that F is a closed, oriented 2-manifold with one component and Euler characteristic 2,
/// every vertex used and every vertex fan a single disc.
bool check_closed_sphere(int nv, const std::vector<Face>& F, std::string* why);

/// The smallest corner angle of the triangle (a, b, c), radians.
double triangle_min_angle(const Vector3d& a, const Vector3d& b, const Vector3d& c);

/// Geometric checks: every triangle has a minimum angle >= min_angle and a normal agreeing with
/// the SDF gradients at its corners (no fold-overs).
bool check_quality(const BodySdf& sdf, const std::vector<Vector3d>& V, const std::vector<Face>& F,
                   double min_angle, std::string* why);

}  // namespace detail
}  // namespace canonform::procedural
