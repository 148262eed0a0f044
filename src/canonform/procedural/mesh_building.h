// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: small helpers shared by the procedural-mesh builders (private to procedural/).
#pragma once

#include "canonform/common/mesh.h"
#include "canonform/common/parallel.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canonform::procedural {
namespace detail {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Face = std::array<int, 3>;

constexpr double kPi = 3.14159265358979323846;

inline double deg(double d) {
    return d * kPi / 180.0;
}

inline Mesh to_trimesh(const std::vector<Vector3d>& V, const std::vector<Face>& F) {
    Mesh m;
    m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
    for (size_t i = 0; i < V.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
    m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
    for (size_t i = 0; i < F.size(); ++i)
        for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(i), k) = F[i][static_cast<size_t>(k)];
    return m;
}

inline std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// Runs fn(begin, end) on chunks of 4096 indices of [0, n), in parallel (canonform::parallel_for).
/// fn must only write to per-index outputs, so results do not depend on the threading.
template <class Fn>
void parallel_ranges(size_t n, const Fn& fn) {
    constexpr size_t kChunk = 4096;
    const auto chunks = static_cast<std::ptrdiff_t>((n + kChunk - 1) / kChunk);
    canonform::parallel_for(chunks, [&](std::ptrdiff_t c, int) {
        const size_t begin = static_cast<size_t>(c) * kChunk;
        fn(begin, std::min(n, begin + kChunk));
    });
}

}  // namespace detail
}  // namespace canonform::procedural
