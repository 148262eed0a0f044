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
