// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: naive surface nets with ambiguity repair. See surface_nets.h.
#include "canonform/procedural/surface_nets.h"
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
namespace {

constexpr int kBlock = 8;  // cells per block edge

struct Block {
    int b[3];
    std::vector<int> ids;     // chains that can matter in this block
    std::vector<double> val;  // (B+1)^3 grid-point values
    std::vector<int> vid;     // B^3 cell vertex ids (-1: none)
};

inline int point_index(int x, int y, int z) {
    return x + (kBlock + 1) * (y + (kBlock + 1) * z);
}
inline int cell_index(int x, int y, int z) {
    return x + kBlock * (y + kBlock * z);
}

/// The values at the 8 corners of cell (x, y, z) of a block (corner m at (m & 1, (m >> 1) & 1,
/// (m >> 2) & 1)) and their inside pattern (bit m set where c[m] < 0).
int cell_corners(const Block& blk, int x, int y, int z, double c[8]) {
    int mask = 0;
    for (int m = 0; m < 8; ++m) {
        c[m] = blk.val[static_cast<size_t>(point_index(x + (m & 1), y + ((m >> 1) & 1), z + ((m >> 2) & 1)))];
        if (c[m] < 0.0) mask |= 1 << m;
    }
    return mask;
}

/// For each of the 256 inside/outside patterns of a cell's corners (bit m = corner m inside;
/// corner m is at (m & 1, (m >> 1) & 1, (m >> 2) & 1)): true if surface nets would not produce a
/// single disc around the cell's vertex, i.e. a face has a checkerboard pattern (its dual edge
/// would get four quads) or the inside or the outside corners are not connected by cube edges.
const std::array<bool, 256>& ambiguous_cells() {
    static const std::array<bool, 256> table = [] {
        std::array<bool, 256> t{};
        auto components = [](int set) {
            int seen = 0, count = 0;
            for (int s = 0; s < 8; ++s) {
                if (!(set >> s & 1) || (seen >> s & 1)) continue;
                ++count;
                int stack[8], top = 0;
                stack[top++] = s;
                seen |= 1 << s;
                while (top > 0) {
                    const int m = stack[--top];
                    for (int bit = 0; bit < 3; ++bit) {
                        const int n = m ^ (1 << bit);
                        if ((set >> n & 1) && !(seen >> n & 1)) {
                            seen |= 1 << n;
                            stack[top++] = n;
                        }
                    }
                }
            }
            return count;
        };
        for (int mask = 0; mask < 256; ++mask) {
            bool bad = components(mask) > 1 || components(~mask & 255) > 1;
            for (int a = 0; a < 3 && !bad; ++a) {
                const int b = 1 << ((a + 1) % 3), c = 1 << ((a + 2) % 3);
                for (int side = 0; side < 2 && !bad; ++side) {
                    const int o = side << a;
                    const bool c00 = mask >> o & 1, c10 = mask >> (o | b) & 1;
                    const bool c11 = mask >> (o | b | c) & 1, c01 = mask >> (o | c) & 1;
                    bad = c00 == c11 && c10 == c01 && c00 != c10;
                }
            }
            t[static_cast<size_t>(mask)] = bad;
        }
        return t;
    }();
    return table;
}

/// Removes the sign patterns that would make surface nets non-manifold (thin slivers where a
/// grid plane grazes the surface) by moving the sign of the offending grid value nearest to zero
/// (|value| < 1.5 h, so the surface moves by less than a cell) to the other side, repeating until
/// no cell is ambiguous. Values shared by neighbouring blocks are changed in all of them.
bool repair_ambiguities(std::vector<Block>* blocks, const std::vector<int>& slot, const int nb[3], double h,
                        std::string* why) {
    const std::array<bool, 256>& ambiguous = ambiguous_cells();
    const double limit = 1.5 * h, tiny = 1e-9 * h;
    auto set_point = [&](const int g[3], double v) {
        int cand[3][2], n_cand[3];
        for (int a = 0; a < 3; ++a) {
            n_cand[a] = 0;
            const int b = g[a] / kBlock;
            if (b < nb[a]) cand[a][n_cand[a]++] = b;
            if (g[a] % kBlock == 0 && b > 0) cand[a][n_cand[a]++] = b - 1;
        }
        for (int i = 0; i < n_cand[0]; ++i)
            for (int j = 0; j < n_cand[1]; ++j)
                for (int k = 0; k < n_cand[2]; ++k) {
                    const int bx = cand[0][i], by = cand[1][j], bz = cand[2][k];
                    const int s =
                        slot[static_cast<size_t>((static_cast<long>(bz) * nb[1] + by) * nb[0] + bx)];
                    if (s < 0) continue;
                    Block& blk = (*blocks)[static_cast<size_t>(s)];
                    blk.val[static_cast<size_t>(
                        point_index(g[0] - bx * kBlock, g[1] - by * kBlock, g[2] - bz * kBlock))] = v;
                }
    };
    for (int pass = 0; pass < 10; ++pass) {
        int flips = 0;
        for (Block& blk : *blocks) {
            for (int z = 0; z < kBlock; ++z)
                for (int y = 0; y < kBlock; ++y)
                    for (int x = 0; x < kBlock; ++x) {
                        double c[8];
                        const int mask = cell_corners(blk, x, y, z, c);
                        if (!ambiguous[static_cast<size_t>(mask)]) continue;
                        // Corners by increasing |value|; flip the first that resolves the cell,
                        // else the one nearest to zero.
                        int order[8];
                        for (int m = 0; m < 8; ++m) order[m] = m;
                        std::sort(order, order + 8, [&](int a, int b) {
                            return std::abs(c[a]) < std::abs(c[b]) ||
                                   (std::abs(c[a]) == std::abs(c[b]) && a < b);
                        });
                        int flip = order[0];
                        for (const int m : order)
                            if (!ambiguous[static_cast<size_t>(mask ^ (1 << m))]) {
                                flip = m;
                                break;
                            }
                        if (std::abs(c[flip]) >= limit) {
                            *why = "surface nets: ambiguous cell far from the surface";
                            return false;
                        }
                        const int g[3] = {blk.b[0] * kBlock + x + (flip & 1),
                                          blk.b[1] * kBlock + y + ((flip >> 1) & 1),
                                          blk.b[2] * kBlock + z + ((flip >> 2) & 1)};
                        set_point(g, c[flip] < 0.0 ? tiny : -tiny);
                        ++flips;
                    }
        }
        if (flips == 0) return true;
    }
    *why = "surface nets: could not resolve ambiguous cells";
    return false;
}
}  // namespace

bool surface_nets(const BodySdf& sdf, const Eigen::AlignedBox3d& box, double h, const Vector3d& shift,
                  bool count_only, long* cell_count, std::vector<Vector3d>* V, std::vector<Face>* F,
                  std::string* why) {
    const Vector3d origin = box.min() - Vector3d::Constant(3.0 * h) - shift * h;
    const Vector3d extent = box.max() + Vector3d::Constant(3.0 * h) - origin;
    int nb[3];
    for (int a = 0; a < 3; ++a) {
        const int cells = static_cast<int>(std::ceil(extent[a] / h));
        nb[a] = (cells + kBlock - 1) / kBlock;
    }
    const long n_blocks = static_cast<long>(nb[0]) * nb[1] * nb[2];
    std::vector<int> slot(static_cast<size_t>(n_blocks), -1);
    std::vector<Block> blocks;

    const double block_radius = 0.5 * std::sqrt(3.0) * kBlock * h;
    // Blocks farther than this from the surface have no sign change, and all their grid values
    // are at least 2h away from zero (so the repair below never touches them).
    const double margin = kLipschitz * block_radius + 2.0 * h;
    const int nc = sdf.num_chains();
    for (int bz = 0; bz < nb[2]; ++bz) {
        for (int by = 0; by < nb[1]; ++by) {
            for (int bx = 0; bx < nb[0]; ++bx) {
                const Vector3d centre = origin + (kBlock * h) * Vector3d(bx + 0.5, by + 0.5, bz + 0.5);
                double cv[kMaxChains];
                double vmin = std::numeric_limits<double>::infinity();
                for (int c = 0; c < nc; ++c) {
                    cv[c] = sdf.chain_value(c, centre, nullptr);
                    vmin = std::min(vmin, cv[c]);
                }
                // Smooth union >= min - k/4: a block is away from the surface if that bound
                // (or min itself, an upper bound) keeps its sign over the whole block.
                if (vmin - 0.25 * sdf.blend() > margin) continue;
                const double d = sdf.eval(centre);
                if (std::abs(d) > margin) continue;
                int ids[kMaxChains];
                int n_ids = 0;
                for (int c = 0; c < nc; ++c)
                    if (cv[c] - margin <= vmin + margin + sdf.blend()) ids[n_ids++] = c;
                Block blk;
                blk.b[0] = bx;
                blk.b[1] = by;
                blk.b[2] = bz;
                blk.ids = std::vector<int>(
                    ids, ids + n_ids);  // (assign() on the empty vector: a GCC 12 -Wnonnull false positive)
                slot[static_cast<size_t>((static_cast<long>(bz) * nb[1] + by) * nb[0] + bx)] =
                    static_cast<int>(blocks.size());
                blocks.push_back(std::move(blk));
            }
        }
    }
    parallel_ranges(blocks.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            Block& blk = blocks[i];
            blk.val.resize((kBlock + 1) * (kBlock + 1) * (kBlock + 1));
            for (int z = 0; z <= kBlock; ++z)
                for (int y = 0; y <= kBlock; ++y)
                    for (int x = 0; x <= kBlock; ++x) {
                        const Vector3d p = origin + h * Vector3d(blk.b[0] * kBlock + x, blk.b[1] * kBlock + y,
                                                                 blk.b[2] * kBlock + z);
                        blk.val[static_cast<size_t>(point_index(x, y, z))] =
                            sdf.eval(p, blk.ids.data(), static_cast<int>(blk.ids.size()), nullptr);
                    }
        }
    });

    if (!count_only && !repair_ambiguities(&blocks, slot, nb, h, why)) return false;

    // One vertex per cell with a sign change, at the mean of the edge crossings.
    static const int kCubeEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                          {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    long count = 0;
    for (Block& blk : blocks) {
        if (!count_only) blk.vid.assign(kBlock * kBlock * kBlock, -1);
        for (int z = 0; z < kBlock; ++z)
            for (int y = 0; y < kBlock; ++y)
                for (int x = 0; x < kBlock; ++x) {
                    double c[8];
                    const int mask = cell_corners(blk, x, y, z, c);
                    if (mask == 0 || mask == 255) continue;
                    ++count;
                    if (count_only) continue;
                    Vector3d sum = Vector3d::Zero();
                    int n = 0;
                    for (const auto& e : kCubeEdges) {
                        const double c0 = c[e[0]], c1 = c[e[1]];
                        if ((c0 < 0.0) == (c1 < 0.0)) continue;
                        const double t = c0 / (c0 - c1);
                        const Vector3d p0((e[0] & 1), ((e[0] >> 1) & 1), ((e[0] >> 2) & 1));
                        const Vector3d p1((e[1] & 1), ((e[1] >> 1) & 1), ((e[1] >> 2) & 1));
                        sum += p0 + t * (p1 - p0);
                        ++n;
                    }
                    const Vector3d local = sum / n;
                    blk.vid[static_cast<size_t>(cell_index(x, y, z))] = static_cast<int>(V->size());
                    V->push_back(origin + h * (Vector3d(blk.b[0] * kBlock + x, blk.b[1] * kBlock + y,
                                                        blk.b[2] * kBlock + z) +
                                               local));
                }
    }
    if (cell_count) *cell_count = count;
    if (count_only) return true;

    auto cell_vertex = [&](int gx, int gy, int gz) -> int {
        if (gx < 0 || gy < 0 || gz < 0) return -1;
        const int bx = gx / kBlock, by = gy / kBlock, bz = gz / kBlock;
        if (bx >= nb[0] || by >= nb[1] || bz >= nb[2]) return -1;
        const int s = slot[static_cast<size_t>((static_cast<long>(bz) * nb[1] + by) * nb[0] + bx)];
        if (s < 0) return -1;
        return blocks[static_cast<size_t>(s)]
            .vid[static_cast<size_t>(cell_index(gx - bx * kBlock, gy - by * kBlock, gz - bz * kBlock))];
    };

    // One quad per grid edge with a sign change, between the four cells around it; split along
    // the shorter diagonal. The edge from p to p + e_a is owned by the cell with min corner p.
    for (const Block& blk : blocks) {
        for (int z = 0; z < kBlock; ++z)
            for (int y = 0; y < kBlock; ++y)
                for (int x = 0; x < kBlock; ++x) {
                    const int l[3] = {x, y, z};
                    const double v0 = blk.val[static_cast<size_t>(point_index(x, y, z))];
                    for (int a = 0; a < 3; ++a) {
                        int l1[3] = {x, y, z};
                        ++l1[a];
                        const double v1 = blk.val[static_cast<size_t>(point_index(l1[0], l1[1], l1[2]))];
                        if ((v0 < 0.0) == (v1 < 0.0)) continue;
                        const int ab = (a + 1) % 3, ac = (a + 2) % 3;  // e_a = e_ab x e_ac
                        int g[3];
                        for (int k = 0; k < 3; ++k) g[k] = blk.b[k] * kBlock + l[k];
                        // Counter-clockwise about +a: offsets (-1,-1), (0,-1), (0,0), (-1,0).
                        static const int kOff[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
                        int q[4];
                        for (int i = 0; i < 4; ++i) {
                            int cg[3] = {g[0], g[1], g[2]};
                            cg[ab] += kOff[i][0];
                            cg[ac] += kOff[i][1];
                            q[i] = cell_vertex(cg[0], cg[1], cg[2]);
                            if (q[i] < 0) {
                                *why = "surface nets: a cell next to a sign change has no vertex";
                                return false;
                            }
                        }
                        // Outward normal is +a when the edge goes from inside to outside.
                        if (!(v0 < 0.0)) std::swap(q[1], q[3]);
                        const Vector3d& p0 = (*V)[static_cast<size_t>(q[0])];
                        const Vector3d& p1 = (*V)[static_cast<size_t>(q[1])];
                        const Vector3d& p2 = (*V)[static_cast<size_t>(q[2])];
                        const Vector3d& p3 = (*V)[static_cast<size_t>(q[3])];
                        if ((p0 - p2).squaredNorm() <= (p1 - p3).squaredNorm()) {
                            F->push_back({q[0], q[1], q[2]});
                            F->push_back({q[0], q[2], q[3]});
                        } else {
                            F->push_back({q[1], q[2], q[3]});
                            F->push_back({q[1], q[3], q[0]});
                        }
                    }
                }
    }
    return true;
}

}  // namespace detail
}  // namespace canonform::procedural
