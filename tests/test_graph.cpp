// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/graph.h"

#include <gtest/gtest.h>

using namespace canonform;
using namespace canonform::numerics;

TEST(Graph, AdjacencyIsSortedAndSymmetric) {
    Eigen::MatrixXi E(4, 2);
    E << 3, 0, 0, 1, 2, 0, 1, 2;
    const VertexAdjacency adj = vertex_adjacency(4, E);
    ASSERT_EQ(adj.num_vertices(), 4);
    auto nbrs = [&](int v) {
        return std::vector<int>(adj.neighbors.begin() + adj.offsets[static_cast<size_t>(v)],
                                adj.neighbors.begin() + adj.offsets[static_cast<size_t>(v) + 1]);
    };
    EXPECT_EQ(nbrs(0), (std::vector<int>{1, 2, 3}));
    EXPECT_EQ(nbrs(1), (std::vector<int>{0, 2}));
    EXPECT_EQ(nbrs(3), (std::vector<int>{0}));
    EXPECT_EQ(adj.neighbors.size(), 8u);
}

TEST(Graph, ComponentsLabelledByLowestVertex) {
    Eigen::MatrixXi E(3, 2);
    E << 5, 4, 1, 3, 3, 0;
    int count = 0;
    const auto label = connected_components(6, E, &count);
    EXPECT_EQ(count, 3);  // {0, 1, 3}, {2}, {4, 5}
    EXPECT_EQ(label, (std::vector<int>{0, 0, 1, 0, 2, 2}));
    EXPECT_EQ(connected_components(3, Eigen::MatrixXi(0, 2), &count), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(count, 3);
}

TEST(Graph, AggregatesAreConnectedAndJoinTheirStrongestNeighbour) {
    // 0-1, 1-2, 2-3, 3-4, 4-5, 5-6; 7 joined to 1 and 5. Pass 1 (index order): {0, 1}, {3, 2, 4},
    // {6, 5}; 7 has no free neighbour left and joins, in pass 2, the aggregate of its stronger one.
    const std::vector<std::pair<int, int>> edges = {{0, 1}, {1, 2}, {2, 3}, {3, 4},
                                                    {4, 5}, {5, 6}, {1, 7}, {5, 7}};
    for (const double to_five : {5.0, 0.2}) {
        WeightedAdjacency g;
        Eigen::MatrixXi E(static_cast<Eigen::Index>(edges.size()), 2);
        for (size_t e = 0; e < edges.size(); ++e)
            E.row(static_cast<Eigen::Index>(e)) << edges[e].first, edges[e].second;
        const VertexAdjacency adj = vertex_adjacency(8, E);
        g.offsets = adj.offsets;
        g.neighbors = adj.neighbors;
        for (size_t p = 0; p < g.neighbors.size(); ++p) g.strengths.push_back(1.0);
        for (int p = g.offsets[7]; p < g.offsets[8]; ++p)
            if (g.neighbors[static_cast<size_t>(p)] == 5) g.strengths[static_cast<size_t>(p)] = to_five;
        int count = 0;
        const std::vector<int> agg = aggregate_vertices(g, &count);
        EXPECT_EQ(count, 3);
        EXPECT_EQ(agg, (std::vector<int>{0, 0, 1, 1, 1, 2, 2, to_five > 1 ? 2 : 0}))
            << "strength to 5: " << to_five;
    }
}

TEST(Graph, AggregatesOfAGridReachTwoEdgesFromTheirCentre) {
    // A 40 x 40 grid with diagonals (a triangulated square): every vertex in one aggregate, every
    // aggregate connected and of diameter at most 4 edges, about a tenth to a third as many
    // aggregates as vertices.
    const int m = 40, n = m * m;
    std::vector<std::pair<int, int>> edges;
    for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x) {
            const int v = y * m + x;
            if (x + 1 < m) edges.emplace_back(v, v + 1);
            if (y + 1 < m) edges.emplace_back(v, v + m);
            if (x + 1 < m && y + 1 < m) edges.emplace_back(v, v + m + 1);
        }
    Eigen::MatrixXi E(static_cast<Eigen::Index>(edges.size()), 2);
    for (size_t e = 0; e < edges.size(); ++e)
        E.row(static_cast<Eigen::Index>(e)) << edges[e].first, edges[e].second;
    const VertexAdjacency adj = vertex_adjacency(n, E);
    WeightedAdjacency g{adj.offsets, adj.neighbors, std::vector<double>(adj.neighbors.size(), 1.0)};
    int count = 0;
    const std::vector<int> agg = aggregate_vertices(g, &count);
    ASSERT_EQ(agg.size(), static_cast<size_t>(n));
    EXPECT_GT(count, n / 10);
    EXPECT_LT(count, n / 3);
    for (int c = 0; c < count; ++c) {
        std::vector<int> members;
        for (int v = 0; v < n; ++v)
            if (agg[static_cast<size_t>(v)] == c) members.push_back(v);
        ASSERT_FALSE(members.empty()) << "aggregate " << c;
        // Breadth-first distances inside the aggregate from each member: all reached within 4.
        for (const int s : members) {
            std::vector<int> dist(static_cast<size_t>(n), -1);
            std::vector<int> queue = {s};
            dist[static_cast<size_t>(s)] = 0;
            for (size_t q = 0; q < queue.size(); ++q) {
                const int v = queue[q];
                for (int p = adj.offsets[static_cast<size_t>(v)]; p < adj.offsets[static_cast<size_t>(v) + 1];
                     ++p) {
                    const int w = adj.neighbors[static_cast<size_t>(p)];
                    if (agg[static_cast<size_t>(w)] != c || dist[static_cast<size_t>(w)] >= 0) continue;
                    dist[static_cast<size_t>(w)] = dist[static_cast<size_t>(v)] + 1;
                    queue.push_back(w);
                }
            }
            for (const int v : members) {
                EXPECT_GE(dist[static_cast<size_t>(v)], 0) << "aggregate " << c << " is not connected";
                EXPECT_LE(dist[static_cast<size_t>(v)], 4) << "aggregate " << c;
            }
        }
    }
}
