// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: combinatorial helpers on an indexed triangle mesh (V #V x 3, F #F x 3).
//
// Undirected edge list, boundary vertices (adjacency and components of the edge graph are in
// canonform/numerics/graph.h), and validate_mesh(), which turns every kind of bad input into an InputError
// naming the problem. Used by every algorithm of the core; no geometry beyond what validation needs.
#pragma once

#include "canonform/numerics/graph.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::surface {

/// Unique undirected edges of F, each as (i, j) with i < j; #E x 2, sorted lexicographically.
Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F);

/// Per vertex: true where the vertex lies on an edge used by exactly one face.
std::vector<bool> boundary_vertices(int n, const Eigen::MatrixXi& F);

/// What validate_mesh() found; filled even when it throws is off.
struct MeshReport {
    int vertices = 0;
    int faces = 0;
    int edges = 0;
    int components = 0;
    int boundary_edges = 0;
    int boundary_loops_vertices = 0;  ///< vertices on a boundary
    int euler_characteristic = 0;     ///< V - E + F
    Eigen::MatrixXi edge_list;        ///< unique_edges(F), #E x 2 (filled once the edges are checked)
    std::vector<bool> boundary;       ///< boundary_vertices(), #V flags (filled with edge_list)
};

/// Options of validate_mesh(): which conditions are errors.
struct ValidationOptions {
    int min_vertices = 10;  ///< fewer vertices is an error
    bool require_single_component = true;
    double degenerate_area = 1e-14;  ///< a face with area below this * (bbox diagonal)^2 is degenerate
    double max_coordinate =
        1e250;  ///< larger |coordinates| are an error (sums and squares must not overflow)
};

/// Checks a triangle mesh and throws InputError with a message naming the first problem found:
/// no vertices, no faces (a point cloud), non-finite coordinates, face indices out of range (checked
/// before F is used), fewer than `min_vertices` vertices, coordinates beyond `max_coordinate`, all
/// vertices at one point, faces with a repeated vertex or (near) zero area relative to the
/// bounding-box diagonal (so 1e-200 and 1e200 coordinates are judged as 1 would be),
/// non-manifold edges (more than two faces), unreferenced vertices, several connected components.
/// Boundaries are allowed (the methods handle them) and reported.
MeshReport validate_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                         const ValidationOptions& options = {});

/// One problem validate_mesh() would refuse a mesh for.
struct MeshProblem {
    std::string kind;  ///< "non_finite", "index_out_of_range", "degenerate_faces", "non_manifold_edges", ...
    std::string message;  ///< validate_mesh()'s message for it
};

/// Every problem validate_mesh() checks for, not just the first (in the same order, with the same
/// messages): an empty list means validate_mesh() accepts the mesh. A check that relies on an
/// earlier one is skipped when that one failed (with face indices out of range nothing that
/// reads F runs; with non-finite coordinates no geometric test). `report`, if given, gets what
/// could be measured. For `canonform check`.
std::vector<MeshProblem> mesh_problems(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const ValidationOptions& options = {}, MeshReport* report = nullptr);

/// Mean over the edges E (#E x 2) of |d1 - d0| / d0, the relative change of each edge's length
/// from the embedding V0 to V1 (both #V x 3; 0 without edges).
double mean_relative_edge_change(const Eigen::MatrixXd& V0, const Eigen::MatrixXd& V1,
                                 const Eigen::MatrixXi& E);

}  // namespace canonform::surface
