// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: coarsening a figure mesh to an exact vertex count on the body's zero set (private to
// procedural/). Not surface/simplify.h: that one collapses by quadric error on a mesh alone; this
// one needs the signed distance (each new vertex is projected onto the zero set, each triangle's
// normal checked against its gradient) and pinned limb-tip vertices, and the figures it makes are
// the test meshes, whose bits must not change.
#pragma once

#include "canonform/procedural/body_model.h"

#include <vector>

namespace canonform::procedural {
namespace detail {

/// Shortest-edge-first collapses (to the edge midpoint projected onto the zero set, or onto the
/// pinned end, which never moves or disappears) until `target` vertices remain. Collapses that
/// would break the manifold (link condition), create a vertex of valence < 4 or > 10, or turn,
/// thin or tilt a triangle away from the surface are skipped. Returns the vertex count reached.
int decimate(const BodySdf& sdf, std::vector<Vector3d>* V, std::vector<Face>* F, std::vector<char>* pinned,
             int target, double max_step);

}  // namespace detail
}  // namespace canonform::procedural
