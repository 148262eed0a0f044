// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: closedness and quality checks of an extracted mesh. See mesh_checks.h.
#include "canonform/procedural/mesh_checks.h"
#include "canonform/procedural/mesh_building.h"
#include "canonform/surface/mesh_topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iterator>
#include <limits>
#include <list>
#include <memory>
#include <mutex>
#include <queue>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace canonform::procedural {
namespace detail {

bool check_closed_sphere(int nv, const std::vector<Face>& F, std::string* why) {
    std::vector<std::uint64_t> de;
    de.reserve(F.size() * 3);
    for (const Face& f : F) {
        if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) {
            *why = "face with a repeated vertex";
            return false;
        }
        for (int k = 0; k < 3; ++k)
            de.push_back(edge_key(f[static_cast<size_t>(k)], f[static_cast<size_t>((k + 1) % 3)]));
    }
    std::sort(de.begin(), de.end());
    for (size_t i = 0; i + 1 < de.size(); ++i)
        if (de[i] == de[i + 1]) {
            *why = "directed edge used twice (non-manifold edge or inconsistent orientation)";
            return false;
        }
    for (const std::uint64_t k : de) {
        const std::uint64_t rev = (k << 32) | (k >> 32);
        if (!std::binary_search(de.begin(), de.end(), rev)) {
            *why = "edge with a single face (boundary)";
            return false;
        }
    }
    // Fans: at vertex v, each face (v, a, b) maps a -> b; the map must be one cycle.
    std::vector<int> deg(static_cast<size_t>(nv), 0);
    for (const Face& f : F)
        for (int k = 0; k < 3; ++k) ++deg[static_cast<size_t>(f[static_cast<size_t>(k)])];
    std::vector<int> off(static_cast<size_t>(nv) + 1, 0);
    for (int v = 0; v < nv; ++v) {
        if (deg[static_cast<size_t>(v)] == 0) {
            *why = "unreferenced vertex";
            return false;
        }
        off[static_cast<size_t>(v) + 1] = off[static_cast<size_t>(v)] + deg[static_cast<size_t>(v)];
    }
    std::vector<std::pair<int, int>> fan(static_cast<size_t>(off.back()));
    std::vector<int> fill(off.begin(), off.end() - 1);
    for (const Face& f : F)
        for (int k = 0; k < 3; ++k) {
            const int v = f[static_cast<size_t>(k)];
            fan[static_cast<size_t>(fill[static_cast<size_t>(v)]++)] = {f[static_cast<size_t>((k + 1) % 3)],
                                                                        f[static_cast<size_t>((k + 2) % 3)]};
        }
    for (int v = 0; v < nv; ++v) {
        const auto first = fan.begin() + off[static_cast<size_t>(v)];
        const auto last = fan.begin() + off[static_cast<size_t>(v) + 1];
        std::sort(first, last);
        // Follow a -> b from the first entry; must return after exactly deg steps.
        int cur = first->first;
        const int start = cur;
        int steps = 0;
        do {
            const auto it =
                std::lower_bound(first, last, std::make_pair(cur, std::numeric_limits<int>::min()));
            if (it == last || it->first != cur) {
                *why = "vertex fan is not closed";
                return false;
            }
            cur = it->second;
            ++steps;
        } while (cur != start && steps <= deg[static_cast<size_t>(v)]);
        if (steps != deg[static_cast<size_t>(v)]) {
            *why = "vertex fan is not a single disc (non-manifold vertex)";
            return false;
        }
    }
    // Components (union-find over edges).
    std::vector<int> parent(static_cast<size_t>(nv));
    for (int v = 0; v < nv; ++v) parent[static_cast<size_t>(v)] = v;
    auto find = [&](int x) {
        while (parent[static_cast<size_t>(x)] != x) {
            parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
            x = parent[static_cast<size_t>(x)];
        }
        return x;
    };
    int components = nv;
    for (const Face& f : F)
        for (int k = 0; k < 3; ++k) {
            const int a = find(f[static_cast<size_t>(k)]), b = find(f[static_cast<size_t>((k + 1) % 3)]);
            if (a != b) {
                parent[static_cast<size_t>(a)] = b;
                --components;
            }
        }
    if (components != 1) {
        *why = "mesh has " + std::to_string(components) + " connected components";
        return false;
    }
    const long euler = static_cast<long>(nv) - static_cast<long>(de.size() / 2) + static_cast<long>(F.size());
    if (euler != 2) {
        *why = "Euler characteristic " + std::to_string(euler) + " (expected 2: genus 0)";
        return false;
    }
    return true;
}

double triangle_min_angle(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    auto angle = [](const Vector3d& p, const Vector3d& q, const Vector3d& r) {
        const Vector3d u = q - p, v = r - p;
        return std::atan2(u.cross(v).norm(), u.dot(v));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

bool check_quality(const BodySdf& sdf, const std::vector<Vector3d>& V, const std::vector<Face>& F,
                   double min_angle, std::string* why) {
    // Outward direction: the SDF gradients at the corners (which lie on the surface).
    std::vector<Vector3d> normal(V.size());
    parallel_ranges(V.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            sdf.eval(V[i], &normal[i]);
            normal[i].normalize();
        }
    });
    std::vector<char> bad(F.size(), 0);  // 1: thin, 2: facing inwards
    parallel_ranges(F.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const Face& f = F[i];
            const Vector3d& a = V[static_cast<size_t>(f[0])];
            const Vector3d& b = V[static_cast<size_t>(f[1])];
            const Vector3d& c = V[static_cast<size_t>(f[2])];
            const Vector3d g = normal[static_cast<size_t>(f[0])] + normal[static_cast<size_t>(f[1])] +
                               normal[static_cast<size_t>(f[2])];
            if (triangle_min_angle(a, b, c) < min_angle)
                bad[i] = 1;
            else if ((b - a).cross(c - a).dot(g) <= 0.0)
                bad[i] = 2;
        }
    });
    for (const char b : bad)
        if (b) {
            *why = b == 1 ? "thin triangle" : "triangle facing inwards";
            return false;
        }
    return true;
}

}  // namespace detail
}  // namespace canonform::procedural
