// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: adjacency and connected components of an undirected graph given as an edge list.
//
// The graph algorithms the numerics need (SMACOF checks that its weight graph is connected) and
// the surface algorithms build on (k-rings, components of a mesh's edge graph).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace canonform::numerics {

/// Vertex adjacency in compressed form: the neighbours of v are
/// neighbors[offsets[v] .. offsets[v+1]), sorted ascending, without v itself.
struct VertexAdjacency {
    std::vector<int> offsets;    ///< size #V + 1
    std::vector<int> neighbors;  ///< size 2 #E
    int num_vertices() const { return static_cast<int>(offsets.size()) - 1; }
};

/// Adjacency of the graph given by an undirected edge list E (#E x 2) on n vertices.
VertexAdjacency vertex_adjacency(int n, const Eigen::MatrixXi& E);

/// Connected-component label per vertex (0-based, in order of lowest vertex index) of the graph
/// with edges E; returns the number of components in *count.
std::vector<int> connected_components(int n, const Eigen::MatrixXi& E, int* count);

}  // namespace canonform::numerics
