// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: quadric edge-collapse simplification (vcglib's TriEdgeCollapseQuadric, the
// algorithm of MeshLab's "Simplification: Quadric Edge Collapse Decimation" filter, with its
// default parameters), for the paper's "simplified to about 2000 vertices" runs.
#pragma once

#include "canonform/common/mesh.h"

namespace canonform::surface {

/// Simplifies the mesh to about `target_vertices` vertices (the face budget is scaled from the
/// current face count). Throws InputError if the target is not below the current count or < 10.
Mesh simplify_mesh(const Mesh& mesh, int target_vertices);

}  // namespace canonform::surface
