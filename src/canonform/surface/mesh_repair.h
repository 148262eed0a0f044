// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: an explicit, logged repair of the defects real collections have, for meshes that
// validate_mesh() refuses (the default everywhere stays strict: repair runs only when asked for,
// `--repair` in the tool and `retrieve`, the filters' "Repair" parameter).
//
// No paper: the steps are the cleaning filters MeshLab offers under the same names, in this order:
//   1. merge duplicate vertices   (vertices with identical coordinates become the first of them;
//                                  MeshLab's "Remove Duplicate Vertices")
//   2. remove degenerate faces    (a repeated vertex, or an area <= degenerate_area x (bounding-box
//                                  diagonal)^2, the same test as validate_mesh(); "Remove Zero Area
//                                  Faces")
//   3. remove duplicate faces     (the same three vertices in any order; the first is kept;
//                                  "Remove Duplicate Faces")
//   4. keep the largest connected component (most faces; ties: the one with the lowest face)
//                                 ("Remove Isolated pieces")
//   5. drop unreferenced vertices ("Remove Unreferenced Vertices")
// It does not invent geometry: NaN coordinates, non-manifold edges and too-small meshes stay
// errors for validate_mesh() to name. Vertex and face order are kept (a kept vertex or face keeps
// its relative position), so results can be mapped back (vertex_source, face_source).
#pragma once

#include "canonform/common/mesh.h"
#include "canonform/common/parameters.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::surface {

/// Options of repair_mesh().
struct MeshRepairOptions {
    double degenerate_area = 1e-14;      ///< as ValidationOptions::degenerate_area
    bool keep_largest_component = true;  ///< step 4
};

/// What repair_mesh() did.
struct MeshRepair {
    Mesh mesh;                       ///< the repaired mesh
    std::vector<int> vertex_source;  ///< #V': the input vertex of each output vertex (increasing)
    std::vector<int> face_source;    ///< #F': the input face of each output face (increasing); the
                                     ///< face's vertices are those of the input face after merging
    int merged_vertices = 0;         ///< vertices merged into an earlier one with equal coordinates
    int degenerate_faces = 0;        ///< faces removed for a zero area or a repeated vertex
    int duplicate_faces = 0;         ///< faces removed as repeats of an earlier one
    int removed_components = 0;      ///< connected components removed (all but the largest)
    int component_faces = 0;         ///< faces those components had
    int unreferenced_vertices = 0;   ///< vertices in no remaining face (after the steps above), dropped
    bool changed() const;
    /// One line: "repair: merged 3 duplicate vertices, removed 5 zero-area or repeated-vertex faces,
    /// ...: 5000 -> 4997 vertices, 9996 -> 9991 faces", or "repair: nothing to repair (...)".
    std::string summary() const;
};

/// The `repair` parameter of every command and filter that reads a mesh (default off: strict).
Parameter repair_parameter();

/// Repairs V (#V x 3) and F (#F x 3, indices in [0, #V): InputError otherwise) by the steps above.
MeshRepair repair_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                       const MeshRepairOptions& options = {});

}  // namespace canonform::surface
