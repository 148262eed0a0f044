// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: naive surface nets of the body's signed distance on a sparse block grid, with the
// sign patterns that would be non-manifold repaired first (private to procedural/).
#pragma once

#include "canonform/procedural/body_model.h"

#include <string>
#include <vector>

namespace canonform::procedural {
namespace detail {

/// Naive surface nets on a sparse block grid of spacing h whose origin is shifted by
/// shift * h (shift in [0,1)^3). If count_only, only counts the cells with a sign change.
/// Returns false (with a reason) if the quads cannot be assembled.
bool surface_nets(const BodySdf& sdf, const Eigen::AlignedBox3d& box, double h, const Vector3d& shift,
                  bool count_only, long* cell_count, std::vector<Vector3d>* V, std::vector<Face>* F,
                  std::string* why);

}  // namespace detail
}  // namespace canonform::procedural
