// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: tangential relaxation of a figure mesh on the body's zero set (private to procedural/).
#pragma once

#include "canonform/procedural/body_model.h"

#include <vector>

namespace canonform::procedural {
namespace detail {

/// Tangential Laplacian smoothing, each step followed by projection onto the zero set. Moves that
/// would make a face turn by more than ~80 degrees from where it started, or face away from the
/// surface normals at its corners, are undone (coarse thin tubes could twist). Pinned vertices
/// stay.
void relax(const BodySdf& sdf, std::vector<Vector3d>* V, const std::vector<Face>& F,
           const std::vector<char>& pinned, int iterations, double lambda, double max_step);

}  // namespace detail
}  // namespace canonform::procedural
