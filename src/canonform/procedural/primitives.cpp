// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the simple procedural shapes (icosphere, torus, disc). See procedural_meshes.h.
#include "canonform/procedural/mesh_building.h"
#include "canonform/procedural/procedural_meshes.h"
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

using namespace detail;

Mesh make_icosphere(int subdivisions, double radius) {
    if (subdivisions < 0 || subdivisions > 9)
        throw std::invalid_argument("make_icosphere: subdivisions must be in [0, 9]");
    if (!(radius > 0.0) || !std::isfinite(radius))
        throw std::invalid_argument("make_icosphere: radius must be positive");
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vector3d> V = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (Vector3d& v : V) v.normalize();
    std::vector<Face> F = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::unordered_map<std::uint64_t, int> mid;
        mid.reserve(F.size() * 2);
        auto midpoint = [&](int a, int b) {
            const std::uint64_t key = edge_key(std::min(a, b), std::max(a, b));
            const auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            const int id = static_cast<int>(V.size());
            V.push_back((V[static_cast<size_t>(a)] + V[static_cast<size_t>(b)]).normalized());
            mid.emplace(key, id);
            return id;
        };
        std::vector<Face> F2;
        F2.reserve(F.size() * 4);
        for (const Face& f : F) {
            const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
            F2.push_back({f[0], ab, ca});
            F2.push_back({f[1], bc, ab});
            F2.push_back({f[2], ca, bc});
            F2.push_back({ab, bc, ca});
        }
        F.swap(F2);
    }
    for (Vector3d& v : V) v *= radius;
    return to_trimesh(V, F);
}

Mesh make_torus(int n_major, int n_minor, double R, double r) {
    if (n_major < 3 || n_minor < 3)
        throw std::invalid_argument("make_torus: n_major and n_minor must be >= 3");
    if (!(r > 0.0) || !(R > r) || !std::isfinite(R))
        throw std::invalid_argument("make_torus: radii must satisfy 0 < r < R");
    std::vector<Vector3d> V;
    V.reserve(static_cast<size_t>(n_major) * static_cast<size_t>(n_minor));
    for (int i = 0; i < n_major; ++i) {
        const double u = 2.0 * kPi * i / n_major;
        for (int j = 0; j < n_minor; ++j) {
            const double v = 2.0 * kPi * j / n_minor;
            const double rho = R + r * std::cos(v);
            V.emplace_back(rho * std::cos(u), rho * std::sin(u), r * std::sin(v));
        }
    }
    // d/du x d/dv points outwards, so (a, a+u, a+u+v) is counter-clockwise seen from outside.
    std::vector<Face> F;
    F.reserve(2 * V.size());
    auto id = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
    for (int i = 0; i < n_major; ++i) {
        for (int j = 0; j < n_minor; ++j) {
            const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            F.push_back({a, b, c});
            F.push_back({a, c, d});
        }
    }
    return to_trimesh(V, F);
}

Mesh make_disc(int target_vertices, double radius) {
    if (target_vertices < 7) throw std::invalid_argument("make_disc: target_vertices must be >= 7");
    if (!(radius > 0.0) || !std::isfinite(radius))
        throw std::invalid_argument("make_disc: radius must be positive");
    // 1 + 3K(K+1) vertices for K rings; pick the K whose count is closest to the target.
    int K = std::max(
        1, static_cast<int>(std::floor((-3.0 + std::sqrt(9.0 + 12.0 * (target_vertices - 1.0))) / 6.0)));
    auto count = [](long k) { return 1 + 3 * k * (k + 1); };
    if (std::abs(count(K + 1) - target_vertices) < std::abs(count(K) - target_vertices)) ++K;

    std::vector<Vector3d> V;
    V.reserve(static_cast<size_t>(count(K)));
    V.emplace_back(0.0, 0.0, 0.0);
    std::vector<int> ring_start(static_cast<size_t>(K) + 1, 0);
    for (int k = 1; k <= K; ++k) {
        ring_start[static_cast<size_t>(k)] = static_cast<int>(V.size());
        const int n = 6 * k;
        const double rho = radius * k / K;
        for (int j = 0; j < n; ++j) {
            const double a = 2.0 * kPi * j / n;
            V.emplace_back(rho * std::cos(a), rho * std::sin(a), 0.0);
        }
    }
    std::vector<Face> F;
    F.reserve(2 * V.size());
    for (int j = 0; j < 6; ++j) F.push_back({0, 1 + j, 1 + (j + 1) % 6});  // centre fan
    for (int k = 2; k <= K; ++k) {
        // Zip ring k-1 (n_in vertices) and ring k (n_out) by angle: advance whichever ring's
        // next vertex comes first. Both rings start at angle 0. Triangles are counter-clockwise.
        const int n_in = 6 * (k - 1), n_out = 6 * k;
        const int s_in = ring_start[static_cast<size_t>(k - 1)], s_out = ring_start[static_cast<size_t>(k)];
        int i = 0, o = 0;
        while (i < n_in || o < n_out) {
            const double next_in = (i < n_in) ? double(i + 1) / n_in : 2.0;
            const double next_out = (o < n_out) ? double(o + 1) / n_out : 2.0;
            const int vi = s_in + i % n_in, vo = s_out + o % n_out;
            if (next_out <= next_in) {
                F.push_back({vi, vo, s_out + (o + 1) % n_out});
                ++o;
            } else {
                F.push_back({vi, vo, s_in + (i + 1) % n_in});
                ++i;
            }
        }
    }
    return to_trimesh(V, F);
}

}  // namespace canonform::procedural
