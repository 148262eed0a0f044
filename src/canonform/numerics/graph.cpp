// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/graph.h"

#include <algorithm>
#include <numeric>

namespace canonform::numerics {

VertexAdjacency vertex_adjacency(int n, const Eigen::MatrixXi& E) {
    VertexAdjacency adj;
    adj.offsets.assign(static_cast<size_t>(n) + 1, 0);
    for (int e = 0; e < E.rows(); ++e) {
        ++adj.offsets[static_cast<size_t>(E(e, 0)) + 1];
        ++adj.offsets[static_cast<size_t>(E(e, 1)) + 1];
    }
    std::partial_sum(adj.offsets.begin(), adj.offsets.end(), adj.offsets.begin());
    adj.neighbors.resize(static_cast<size_t>(adj.offsets.back()));
    std::vector<int> fill(adj.offsets.begin(), adj.offsets.end() - 1);
    for (int e = 0; e < E.rows(); ++e) {
        const int a = E(e, 0), b = E(e, 1);
        adj.neighbors[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = b;
        adj.neighbors[static_cast<size_t>(fill[static_cast<size_t>(b)]++)] = a;
    }
    for (int v = 0; v < n; ++v)
        std::sort(adj.neighbors.begin() + adj.offsets[static_cast<size_t>(v)],
                  adj.neighbors.begin() + adj.offsets[static_cast<size_t>(v) + 1]);
    return adj;
}

std::vector<int> aggregate_vertices(const WeightedAdjacency& graph, int* count) {
    const std::vector<int>& offsets = graph.offsets;
    const std::vector<int>& nb = graph.neighbors;
    const int n = static_cast<int>(offsets.size()) - 1;
    std::vector<int> agg(static_cast<size_t>(n), -1);
    int next = 0;
    // Pass 1: a vertex whose neighbours are all free starts an aggregate with them.
    for (int i = 0; i < n; ++i) {
        if (agg[static_cast<size_t>(i)] >= 0) continue;
        const int b = offsets[static_cast<size_t>(i)], e = offsets[static_cast<size_t>(i) + 1];
        if (b == e) continue;  // no neighbour: left for pass 3
        bool free = true;
        for (int p = b; p < e && free; ++p) free = agg[static_cast<size_t>(nb[static_cast<size_t>(p)])] < 0;
        if (!free) continue;
        agg[static_cast<size_t>(i)] = next;
        for (int p = b; p < e; ++p) agg[static_cast<size_t>(nb[static_cast<size_t>(p)])] = next;
        ++next;
    }
    // Pass 2: a free vertex joins the pass-1 aggregate of its strongest aggregated neighbour.
    const std::vector<int> pass1 = agg;
    for (int i = 0; i < n; ++i) {
        if (agg[static_cast<size_t>(i)] >= 0) continue;
        double best = -1;
        for (int p = offsets[static_cast<size_t>(i)]; p < offsets[static_cast<size_t>(i) + 1]; ++p) {
            const int j = nb[static_cast<size_t>(p)];
            if (pass1[static_cast<size_t>(j)] >= 0 && graph.strengths[static_cast<size_t>(p)] > best) {
                best = graph.strengths[static_cast<size_t>(p)];
                agg[static_cast<size_t>(i)] = pass1[static_cast<size_t>(j)];
            }
        }
    }
    // Pass 3: what is still free starts an aggregate with its free neighbours (or alone).
    for (int i = 0; i < n; ++i) {
        if (agg[static_cast<size_t>(i)] >= 0) continue;
        agg[static_cast<size_t>(i)] = next;
        for (int p = offsets[static_cast<size_t>(i)]; p < offsets[static_cast<size_t>(i) + 1]; ++p) {
            const int j = nb[static_cast<size_t>(p)];
            if (agg[static_cast<size_t>(j)] < 0) agg[static_cast<size_t>(j)] = next;
        }
        ++next;
    }
    if (count) *count = next;
    return agg;
}

std::vector<int> connected_components(int n, const Eigen::MatrixXi& E, int* count) {
    // Union-find with path halving.
    std::vector<int> parent(static_cast<size_t>(n));
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
        while (parent[static_cast<size_t>(x)] != x) {
            parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
            x = parent[static_cast<size_t>(x)];
        }
        return x;
    };
    for (int e = 0; e < E.rows(); ++e) {
        int a = find(E(e, 0)), b = find(E(e, 1));
        if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
    }
    std::vector<int> label(static_cast<size_t>(n), -1);
    int c = 0;
    for (int v = 0; v < n; ++v) {
        const int r = find(v);
        if (label[static_cast<size_t>(r)] < 0) label[static_cast<size_t>(r)] = c++;
        label[static_cast<size_t>(v)] = label[static_cast<size_t>(r)];
    }
    if (count) *count = c;
    return label;
}

}  // namespace canonform::numerics
