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

/// A graph in compressed form whose edges have strengths: the neighbours of v are
/// neighbors[offsets[v] .. offsets[v+1]), the edge to neighbors[p] has strength strengths[p] > 0.
struct WeightedAdjacency {
    std::vector<int> offsets;       ///< size #V + 1
    std::vector<int> neighbors;     ///< size 2 #E
    std::vector<double> strengths;  ///< size 2 #E
};

/// Aggregates of a graph for a multilevel method, after P. Vanek, J. Mandel, M. Brezina,
/// "Algebraic multigrid by smoothed aggregation", Computing 56, 1996, in three passes over the
/// vertices in index order: (1) a vertex whose neighbours are all free starts an aggregate with
/// them; (2) a vertex still free joins the pass-1 aggregate of its strongest neighbour in one (the
/// first such neighbour on a tie); (3) what is still free starts an aggregate with its free
/// neighbours (or alone). Every aggregate is connected, and each of its vertices is at most two
/// edges from the vertex that started it. Returns the aggregate of every vertex (0-based, in
/// order of creation) and their number in *count.
std::vector<int> aggregate_vertices(const WeightedAdjacency& graph, int* count);

/// Connected-component label per vertex (0-based, in order of lowest vertex index) of the graph
/// with edges E; returns the number of components in *count.
std::vector<int> connected_components(int n, const Eigen::MatrixXi& E, int* count);

}  // namespace canonform::numerics
