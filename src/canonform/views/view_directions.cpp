// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/view_directions.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace canonform::views {

namespace {

std::vector<Eigen::Vector3d> build_view_directions() {
    std::vector<Eigen::Vector3d> P = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    // Octahedron faces (orientation is irrelevant: only the vertex set is used).
    std::vector<std::array<int, 3>> T = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                         {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int level = 0; level < 2; ++level) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const std::pair<int, int> key(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            const int id = static_cast<int>(P.size());
            P.push_back((P[a] + P[b]).normalized());
            mid.emplace(key, id);
            return id;
        };
        std::vector<std::array<int, 3>> T2;
        T2.reserve(4 * T.size());
        for (const auto& t : T) {
            const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
            T2.push_back({t[0], ab, ca});
            T2.push_back({t[1], bc, ab});
            T2.push_back({t[2], ca, bc});
            T2.push_back({ab, bc, ca});
        }
        T.swap(T2);
    }
    auto key = [](const Eigen::Vector3d& d) {
        return std::array<long long, 3>{std::llround(d.x() * 1e9), std::llround(d.y() * 1e9),
                                        std::llround(d.z() * 1e9)};
    };
    std::sort(P.begin(), P.end(),
              [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return key(a) < key(b); });
    if (static_cast<int>(P.size()) != kNumViews)
        throw NumericalError("view_directions: the subdivided octahedron does not have 66 vertices");
    return P;
}

std::vector<Eigen::Matrix3d> build_cube_rotations() {
    std::vector<Eigen::Matrix3d> out;
    std::array<int, 3> p = {0, 1, 2};
    do {
        for (int signs = 0; signs < 8; ++signs) {
            Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
            for (int i = 0; i < 3; ++i) R(i, p[i]) = ((signs >> (2 - i)) & 1) ? -1.0 : 1.0;
            if (R.determinant() > 0) out.push_back(R);
        }
    } while (std::next_permutation(p.begin(), p.end()));
    return out;
}

std::vector<std::vector<int>> build_maps() {
    const std::vector<Eigen::Vector3d>& D = view_directions();
    const std::vector<Eigen::Matrix3d> Rs = cube_rotations();
    std::vector<std::vector<int>> maps(Rs.size(), std::vector<int>(D.size(), -1));
    for (size_t r = 0; r < Rs.size(); ++r) {
        std::vector<char> hit(D.size(), 0);
        for (size_t i = 0; i < D.size(); ++i) {
            const Eigen::Vector3d img = Rs[r] * D[i];
            int best = -1;
            double best_d = 1e300;
            for (size_t j = 0; j < D.size(); ++j) {
                const double dj = (D[j] - img).norm();
                if (dj < best_d) best_d = dj, best = static_cast<int>(j);
            }
            if (!(best_d <= 1e-9) || hit[static_cast<size_t>(best)])
                throw NumericalError(
                    "rotation_view_maps: a cube rotation does not map the view "
                    "directions onto themselves");
            hit[static_cast<size_t>(best)] = 1;
            maps[r][i] = best;
        }
    }
    return maps;
}

std::vector<int> build_opposites() {
    const std::vector<Eigen::Vector3d>& D = view_directions();
    std::vector<int> opposite(D.size(), -1);
    for (size_t i = 0; i < D.size(); ++i)
        for (size_t j = 0; j < D.size(); ++j)
            if (D[j] == -D[i]) opposite[i] = static_cast<int>(j);
    for (int j : opposite)
        if (j < 0) throw NumericalError("opposite_views: a view direction has no exact opposite");
    return opposite;
}

}  // namespace

std::vector<int> opposite_views() {
    static const std::vector<int> opposite = build_opposites();
    return opposite;
}

std::vector<Eigen::Vector3d> view_directions() {
    static const std::vector<Eigen::Vector3d> dirs = build_view_directions();
    return dirs;
}

std::vector<Eigen::Matrix3d> cube_rotations() {
    static const std::vector<Eigen::Matrix3d> rots = build_cube_rotations();
    return rots;
}

std::vector<std::vector<int>> rotation_view_maps() {
    static const std::vector<std::vector<int>> maps = build_maps();
    return maps;
}

}  // namespace canonform::views
