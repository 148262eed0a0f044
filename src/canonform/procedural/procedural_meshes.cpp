// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: procedural test meshes. See procedural_meshes.h.
#include "canonform/procedural/procedural_meshes.h"

#include "canonform/common/parallel.h"
#include "canonform/surface/mesh_topology.h"

#include <Eigen/Geometry>

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
#include <vector>

namespace canonform::procedural {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Face = std::array<int, 3>;

constexpr double kPi = 3.14159265358979323846;

double deg(double d) {
    return d * kPi / 180.0;
}

Mesh to_trimesh(const std::vector<Vector3d>& V, const std::vector<Face>& F) {
    Mesh m;
    m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
    for (size_t i = 0; i < V.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
    m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
    for (size_t i = 0; i < F.size(); ++i)
        for (int k = 0; k < 3; ++k)
            m.F(static_cast<Eigen::Index>(i), k) = F[i][static_cast<size_t>(k)];
    return m;
}

std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
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

}  // namespace

// ================================================================================= simple shapes

Mesh make_icosphere(int subdivisions, double radius) {
    if (subdivisions < 0 || subdivisions > 9)
        throw std::invalid_argument("make_icosphere: subdivisions must be in [0, 9]");
    if (!(radius > 0.0) || !std::isfinite(radius))
        throw std::invalid_argument("make_icosphere: radius must be positive");
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vector3d> V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
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
            const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                      ca = midpoint(f[2], f[0]);
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
    int K = std::max(1, static_cast<int>(std::floor(
                            (-3.0 + std::sqrt(9.0 + 12.0 * (target_vertices - 1.0))) / 6.0)));
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
        const int s_in = ring_start[static_cast<size_t>(k - 1)],
                  s_out = ring_start[static_cast<size_t>(k)];
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

// ======================================================================================= figure

namespace {

// ------------------------------------------------------------------------------- body model

enum BoneId : int {
    kRoot = 0,
    kHead,
    kLUpperArm,
    kLLowerArm,
    kRUpperArm,
    kRLowerArm,
    kLUpperLeg,
    kLLowerLeg,
    kRUpperLeg,
    kRLowerLeg,
    kTail1,
    kTail2,
    kTail3,
    kNumBones
};

/// Tapered capsule: points within radius ra + t (rb - ra) of a + t (b - a), t in [0, 1].
struct Capsule {
    Vector3d a, b;
    double ra, rb;
    int bone;
};

/// Distance-like function of a tapered capsule (exact for ra == rb) and its gradient.
double capsule_eval(const Capsule& c, const Vector3d& p, Vector3d* grad) {
    const Vector3d ab = c.b - c.a;
    const double len2 = ab.squaredNorm();
    double t = (p - c.a).dot(ab) / len2;
    bool interior = true;
    if (t <= 0.0) {
        t = 0.0;
        interior = false;
    } else if (t >= 1.0) {
        t = 1.0;
        interior = false;
    }
    const Vector3d d = p - (c.a + t * ab);
    const double dist = d.norm();
    if (grad) {
        *grad = dist > 1e-300 ? Vector3d(d / dist) : Vector3d(0, 0, 1);
        if (interior) *grad -= (c.rb - c.ra) / len2 * ab;
    }
    return dist - (c.ra + t * (c.rb - c.ra));
}

/// Distance from p to the capsule's axis divided by the radius there (1 on the capsule surface).
double capsule_normalized_distance(const Capsule& c, const Vector3d& p) {
    const Vector3d ab = c.b - c.a;
    const double t = std::clamp((p - c.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (c.a + t * ab)).norm() / (c.ra + t * (c.rb - c.ra));
}

/// A body part: hard union (min) of capsules (the segments of one limb share radii at the joints).
struct Chain {
    std::vector<Capsule> caps;
    Vector3d centre = Vector3d::Zero();  ///< bounding sphere of the solid
    double radius = 0.0;
};

struct Bone {
    int parent;
    Vector3d joint;  ///< rest-pose pivot
};

constexpr int kMaxChains = 16;
constexpr int kMaxCapsules = 32;

struct Body {
    std::vector<Chain> chains;   ///< smooth-unioned parts
    std::vector<Capsule> caps;   ///< all capsules (for skinning weights)
    std::vector<Bone> bones;     ///< kNumBones, parents before children
    double blend = 0.07;         ///< smooth-min radius k between parts
    std::vector<Vector3d> tips;  ///< rest-pose limb tips (on the capsule surface)
    std::vector<double> tip_radius;
    std::vector<std::string> tip_names;
    Eigen::AlignedBox3d box;  ///< contains the surface
    double min_radius = 0.0;
};

Vector3d mirror_x(const Vector3d& p) {
    return Vector3d(-p.x(), p.y(), p.z());
}

Body build_body() {
    Body b;
    auto add_chain = [&](std::vector<Capsule> caps) { b.chains.push_back(Chain{std::move(caps)}); };
    // Trunk (root bone): torso, shoulder girdle, hips.
    add_chain({{{0, 0, 0.92}, {0, 0, 1.40}, 0.19, 0.19, kRoot}});
    add_chain({{{-0.26, 0, 1.44}, {0.26, 0, 1.44}, 0.10, 0.10, kRoot}});
    add_chain({{{-0.12, 0, 0.90}, {0.12, 0, 0.90}, 0.13, 0.13, kRoot}});
    // Neck and head; the head is elongated front-back so that turning it changes the shape.
    add_chain({{{0, 0, 1.45}, {0, 0, 1.70}, 0.065, 0.065, kHead}});
    add_chain({{{0, 0.03, 1.82}, {0, -0.05, 1.82}, 0.14, 0.14, kHead}});
    // Arms (T-pose): shoulder, elbow, wrist.
    const Vector3d sh(0.26, 0, 1.44), el(0.60, 0, 1.44), wr(0.93, 0, 1.44);
    const double r_sh = 0.065, r_el = 0.055, r_wr = 0.045;
    add_chain({{sh, el, r_sh, r_el, kLUpperArm}, {el, wr, r_el, r_wr, kLLowerArm}});
    add_chain({{mirror_x(sh), mirror_x(el), r_sh, r_el, kRUpperArm},
               {mirror_x(el), mirror_x(wr), r_el, r_wr, kRLowerArm}});
    // Legs, spread outwards: hip, knee, ankle.
    const Vector3d hp(0.12, 0, 0.88), kn(0.23, 0, 0.48), an(0.34, 0, 0.07);
    const double r_hp = 0.08, r_kn = 0.068, r_an = 0.052;
    add_chain({{hp, kn, r_hp, r_kn, kLUpperLeg}, {kn, an, r_kn, r_an, kLLowerLeg}});
    add_chain({{mirror_x(hp), mirror_x(kn), r_hp, r_kn, kRUpperLeg},
               {mirror_x(kn), mirror_x(an), r_kn, r_an, kRLowerLeg}});
    // Tail, straight back from the lower back.
    const Vector3d t0(0, 0.10, 0.86), t1(0, 0.40, 0.74), t2(0, 0.68, 0.70), t3(0, 0.92, 0.74);
    add_chain({{t0, t1, 0.060, 0.052, kTail1},
               {t1, t2, 0.052, 0.045, kTail2},
               {t2, t3, 0.045, 0.040, kTail3}});

    b.bones.resize(kNumBones);
    b.bones[kRoot] = {-1, Vector3d(0, 0, 0.9)};
    b.bones[kHead] = {kRoot, Vector3d(0, 0, 1.50)};
    b.bones[kLUpperArm] = {kRoot, sh};
    b.bones[kLLowerArm] = {kLUpperArm, el};
    b.bones[kRUpperArm] = {kRoot, mirror_x(sh)};
    b.bones[kRLowerArm] = {kRUpperArm, mirror_x(el)};
    b.bones[kLUpperLeg] = {kRoot, hp};
    b.bones[kLLowerLeg] = {kLUpperLeg, kn};
    b.bones[kRUpperLeg] = {kRoot, mirror_x(hp)};
    b.bones[kRLowerLeg] = {kRUpperLeg, mirror_x(kn)};
    b.bones[kTail1] = {kRoot, t0};
    b.bones[kTail2] = {kTail1, t1};
    b.bones[kTail3] = {kTail2, t2};

    const Vector3d foot_dir = (an - kn).normalized(), tail_dir = (t3 - t2).normalized();
    b.tip_names = {"head", "left_hand", "right_hand", "left_foot", "right_foot", "tail"};
    const Vector3d head_top(0, -0.01, 1.82 + 0.14), hand = wr + r_wr * Vector3d::UnitX(),
                                                    foot = an + r_an * foot_dir;
    b.tips = {head_top, hand, mirror_x(hand), foot, mirror_x(foot), t3 + 0.040 * tail_dir};
    b.tip_radius = {0.14, r_wr, r_wr, r_an, r_an, 0.040};

    for (Chain& ch : b.chains) {
        Eigen::AlignedBox3d bb;
        for (const Capsule& c : ch.caps) bb.extend(c.a).extend(c.b);
        ch.centre = bb.center();
        for (const Capsule& c : ch.caps)
            ch.radius = std::max(
                {ch.radius, (c.a - ch.centre).norm() + c.ra, (c.b - ch.centre).norm() + c.rb});
    }
    b.box.setEmpty();
    b.min_radius = std::numeric_limits<double>::infinity();
    for (const Chain& ch : b.chains) {
        for (const Capsule& c : ch.caps) {
            b.caps.push_back(c);
            b.box.extend(c.a - Vector3d::Constant(c.ra));
            b.box.extend(c.a + Vector3d::Constant(c.ra));
            b.box.extend(c.b - Vector3d::Constant(c.rb));
            b.box.extend(c.b + Vector3d::Constant(c.rb));
            b.min_radius = std::min({b.min_radius, c.ra, c.rb});
        }
    }
    // The smooth min moves the surface outwards by at most k/4.
    b.box.min() -= Vector3d::Constant(0.25 * b.blend + 1e-3);
    b.box.max() += Vector3d::Constant(0.25 * b.blend + 1e-3);
    return b;
}

const Body& the_body() {
    static const Body body = build_body();
    return body;
}

/// Bound on |grad| of a chain's value (tapered capsules: sqrt(1 + taper^2) < 1.01) and hence of
/// the smooth union (whose gradient is a convex combination of the chains' gradients).
constexpr double kLipschitz = 1.1;

/// Signed distance-like function of the rest body: negative inside. Parts are combined by a
/// polynomial smooth min, folded in increasing order of their values, which makes the result a
/// symmetric function of the part values in which every part farther than k from the nearest one
/// is an exact no-op (so evaluating only the parts that can be within k gives identical values).
class BodySdf {
public:
    explicit BodySdf(const Body& body) : body_(body), k_(body.blend) {}

    int num_chains() const { return static_cast<int>(body_.chains.size()); }
    double blend() const { return k_; }

    double chain_value(int c, const Vector3d& p, Vector3d* grad) const {
        const Chain& ch = body_.chains[static_cast<size_t>(c)];
        double best = std::numeric_limits<double>::infinity();
        Vector3d g = Vector3d::Zero();
        for (const Capsule& cap : ch.caps) {
            const double d = capsule_eval(cap, p, grad ? &g : nullptr);
            if (d < best) {
                best = d;
                if (grad) *grad = g;
            }
        }
        return best;
    }

    /// Smooth union of the chains ids[0..n) at p (and its gradient if grad != nullptr).
    /// Chains are visited by increasing bounding-sphere lower bound and skipped once that bound is
    /// k above the smallest value found: such chains are no-ops in the fold (exact).
    double eval(const Vector3d& p, const int* ids, int n, Vector3d* grad) const {
        if (n <= 0) return std::numeric_limits<double>::infinity();
        double lower[kMaxChains] = {};
        int visit[kMaxChains] = {};
        for (int i = 0; i < n; ++i) {
            const Chain& ch = body_.chains[static_cast<size_t>(ids[i])];
            lower[i] = (p - ch.centre).norm() - ch.radius;
            visit[i] = i;
            for (int j = i; j > 0 && lower[visit[j]] < lower[visit[j - 1]]; --j)
                std::swap(visit[j], visit[j - 1]);
        }
        double val[kMaxChains] = {};
        Vector3d gr[kMaxChains];
        for (Vector3d& x : gr) x.setZero();
        int order[kMaxChains] = {};
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const int c = visit[i];
            if (m > 0 && lower[c] >= val[order[0]] + k_) break;
            val[m] = chain_value(ids[c], p, grad ? &gr[m] : nullptr);
            order[m] = m;
            for (int j = m; j > 0 && val[order[j]] < val[order[j - 1]]; --j)
                std::swap(order[j], order[j - 1]);
            ++m;
        }
        double r = val[order[0]];
        Vector3d g = Vector3d::Zero();
        if (grad) g = gr[order[0]];
        for (int j = 1; j < m; ++j) {
            const double diff = val[order[j]] - r;  // >= 0: r <= every value so far
            if (diff >= k_) break;                  // sorted: all later parts are no-ops too
            const double h = (k_ - diff) / k_;
            r -= 0.25 * h * h * k_;
            if (grad) g = (1.0 - 0.5 * h) * g + (0.5 * h) * gr[order[j]];
        }
        if (grad) *grad = g;
        return r;
    }

    double eval(const Vector3d& p, Vector3d* grad = nullptr) const {
        return eval(p, all_ids(), num_chains(), grad);
    }

    /// The chains that can matter anywhere within distance rho of p: evaluating only them there
    /// gives exactly eval(). Writes their ids (ascending) and returns their number.
    int relevant_chains(const Vector3d& p, double rho, int* ids) const {
        const int n = num_chains();
        double v[kMaxChains];
        double vmin = std::numeric_limits<double>::infinity();
        for (int c = 0; c < n; ++c) {
            const Chain& ch = body_.chains[static_cast<size_t>(c)];
            const double lower = (p - ch.centre).norm() - ch.radius;
            // A chain whose lower bound is already far above the best value cannot matter.
            v[c] = (lower - kLipschitz * rho > vmin + kLipschitz * rho + k_)
                       ? std::numeric_limits<double>::infinity()
                       : chain_value(c, p, nullptr);
            vmin = std::min(vmin, v[c]);
        }
        int m = 0;
        for (int c = 0; c < n; ++c)
            if (v[c] - kLipschitz * rho <= vmin + kLipschitz * rho + k_) ids[m++] = c;
        return m;
    }

    /// Moves p onto the zero set by Newton steps along the gradient (each step at most max_step).
    /// With ids, only those chains are evaluated (see relevant_chains()).
    /// If last_grad is given, it receives the gradient at the last point evaluated.
    Vector3d project(Vector3d p, int steps, double max_step, const int* ids = nullptr,
                     int n_ids = 0, Vector3d* last_grad = nullptr) const {
        for (int s = 0; s < steps; ++s) {
            Vector3d g = Vector3d::Zero();
            const double f = ids ? eval(p, ids, n_ids, &g) : eval(p, &g);
            if (last_grad) *last_grad = g;
            const double gg = g.squaredNorm();
            if (gg < 1e-12) break;
            Vector3d step = (f / gg) * g;
            const double len = step.norm();
            if (len > max_step) step *= max_step / len;
            p -= step;
            if (len < 1e-12) break;
        }
        return p;
    }

private:
    const int* all_ids() const {
        static const std::array<int, kMaxChains> ids = [] {
            std::array<int, kMaxChains> a{};
            for (int i = 0; i < kMaxChains; ++i) a[static_cast<size_t>(i)] = i;
            return a;
        }();
        return ids.data();
    }

    const Body& body_;
    double k_;
};

// ------------------------------------------------------------------------------ surface nets

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
bool repair_ambiguities(std::vector<Block>* blocks, const std::vector<int>& slot, const int nb[3],
                        double h, std::string* why) {
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
                    const int s = slot[static_cast<size_t>(
                        (static_cast<long>(bz) * nb[1] + by) * nb[0] + bx)];
                    if (s < 0) continue;
                    Block& blk = (*blocks)[static_cast<size_t>(s)];
                    blk.val[static_cast<size_t>(point_index(g[0] - bx * kBlock, g[1] - by * kBlock,
                                                            g[2] - bz * kBlock))] = v;
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

/// Naive surface nets on a sparse block grid of spacing h whose origin is shifted by
/// shift * h (shift in [0,1)^3). If count_only, only counts the cells with a sign change.
/// Returns false (with a reason) if the quads cannot be assembled.
bool surface_nets(const BodySdf& sdf, const Eigen::AlignedBox3d& box, double h,
                  const Vector3d& shift, bool count_only, long* cell_count,
                  std::vector<Vector3d>* V, std::vector<Face>* F, std::string* why) {
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
                const Vector3d centre =
                    origin + (kBlock * h) * Vector3d(bx + 0.5, by + 0.5, bz + 0.5);
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
                blk.ids = std::vector<int>(ids, ids + n_ids);  // (assign() on the empty vector: a GCC 12 -Wnonnull false positive)
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
                        const Vector3d p =
                            origin + h * Vector3d(blk.b[0] * kBlock + x, blk.b[1] * kBlock + y,
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
                    V->push_back(origin +
                                 h * (Vector3d(blk.b[0] * kBlock + x, blk.b[1] * kBlock + y,
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
        return blocks[static_cast<size_t>(s)].vid[static_cast<size_t>(
            cell_index(gx - bx * kBlock, gy - by * kBlock, gz - bz * kBlock))];
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
                        const double v1 =
                            blk.val[static_cast<size_t>(point_index(l1[0], l1[1], l1[2]))];
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

// ------------------------------------------------------------------------- mesh bookkeeping

/// Checks that F is a closed, oriented 2-manifold with one component and Euler characteristic 2,
/// every vertex used and every vertex fan a single disc.
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
            fan[static_cast<size_t>(fill[static_cast<size_t>(v)]++)] = {
                f[static_cast<size_t>((k + 1) % 3)], f[static_cast<size_t>((k + 2) % 3)]};
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
            parent[static_cast<size_t>(x)] =
                parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
            x = parent[static_cast<size_t>(x)];
        }
        return x;
    };
    int components = nv;
    for (const Face& f : F)
        for (int k = 0; k < 3; ++k) {
            const int a = find(f[static_cast<size_t>(k)]),
                      b = find(f[static_cast<size_t>((k + 1) % 3)]);
            if (a != b) {
                parent[static_cast<size_t>(a)] = b;
                --components;
            }
        }
    if (components != 1) {
        *why = "mesh has " + std::to_string(components) + " connected components";
        return false;
    }
    const long euler =
        static_cast<long>(nv) - static_cast<long>(de.size() / 2) + static_cast<long>(F.size());
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

/// Geometric checks: every triangle has a minimum angle >= min_angle and a normal agreeing with
/// the SDF gradients at its corners (no fold-overs).
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
            const Vector3d g = normal[static_cast<size_t>(f[0])] +
                               normal[static_cast<size_t>(f[1])] +
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

// ------------------------------------------------------------------------------- relaxation

/// Tangential Laplacian smoothing, each step followed by projection onto the zero set. Moves that
/// would make a face turn by more than ~80 degrees from where it started, or face away from the
/// surface normals at its corners, are undone (coarse thin tubes could twist). Pinned vertices
/// stay.
void relax(const BodySdf& sdf, std::vector<Vector3d>* V, const std::vector<Face>& F,
           const std::vector<char>& pinned, int iterations, double lambda, double max_step) {
    const size_t nv = V->size();
    const numerics::VertexAdjacency adjacency = numerics::vertex_adjacency(static_cast<int>(nv), surface::unique_edges(to_trimesh({}, F).F));
    const std::vector<int>& off = adjacency.offsets;
    const std::vector<int>& nb = adjacency.neighbors;
    const std::vector<Vector3d> start = *V;
    std::vector<Vector3d> next(nv), normal(nv), next_normal(nv);
    parallel_ranges(nv, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) {
            sdf.eval((*V)[v], &normal[v]);
            normal[v].normalize();
        }
    });
    std::vector<char> bad(F.size());
    for (int it = 0; it < iterations; ++it) {
        parallel_ranges(nv, [&](size_t begin, size_t end) {
            for (size_t v = begin; v < end; ++v) {
                const Vector3d& p = (*V)[v];
                next[v] = p;
                next_normal[v] = normal[v];
                if (pinned[v]) continue;
                const int b = off[v], e = off[v + 1];
                Vector3d c = Vector3d::Zero();
                for (int i = b; i < e; ++i)
                    c += (*V)[static_cast<size_t>(nb[static_cast<size_t>(i)])];
                c /= std::max(1, e - b);
                Vector3d d = c - p;
                // Everything below is evaluated within rho of p.
                int ids[kMaxChains];
                const int n_ids = sdf.relevant_chains(p, lambda * d.norm() + 2.0 * max_step, ids);
                Vector3d g = Vector3d::Zero();
                sdf.eval(p, ids, n_ids, &g);
                const double gn = g.norm();
                if (gn > 1e-12) {
                    const Vector3d n = g / gn;
                    d -= n.dot(d) * n;
                }
                next[v] = sdf.project(p + lambda * d, 2, max_step, ids, n_ids, &g);
                if (g.norm() > 1e-12) next_normal[v] = g.normalized();
            }
        });
        for (bool changed = true; changed;) {
            changed = false;
            parallel_ranges(F.size(), [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    const Face& f = F[i];
                    Vector3d o[3], q[3], sn = Vector3d::Zero();
                    for (int k = 0; k < 3; ++k) {
                        const size_t x = static_cast<size_t>(f[static_cast<size_t>(k)]);
                        o[k] = start[x];
                        q[k] = next[x];
                        sn += next_normal[x];
                    }
                    const Vector3d n_old = (o[1] - o[0]).cross(o[2] - o[0]);
                    const Vector3d n_new = (q[1] - q[0]).cross(q[2] - q[0]);
                    const double ln = n_new.norm();
                    bad[i] = n_new.dot(n_old) <= 0.2 * ln * n_old.norm() ||
                             n_new.dot(sn) <= 0.2 * ln * sn.norm();
                }
            });
            for (size_t i = 0; i < F.size(); ++i) {
                if (!bad[i]) continue;
                for (const int x : F[i]) {
                    const size_t v = static_cast<size_t>(x);
                    if (next[v] != (*V)[v]) {
                        next[v] = (*V)[v];
                        next_normal[v] = normal[v];
                        changed = true;
                    }
                }
            }
        }
        V->swap(next);
        normal.swap(next_normal);
    }
}

// ------------------------------------------------------------------------------- decimation

/// Shortest-edge-first collapses (to the edge midpoint projected onto the zero set, or onto the
/// pinned end, which never moves or disappears) until `target` vertices remain. Collapses that
/// would break the manifold (link condition), create a vertex of valence < 4 or > 10, or turn,
/// thin or tilt a triangle away from the surface are skipped. Returns the vertex count reached.
int decimate(const BodySdf& sdf, std::vector<Vector3d>* V, std::vector<Face>* F,
             std::vector<char>* pinned, int target, double max_step) {
    const int nv = static_cast<int>(V->size());
    std::vector<Vector3d>& P = *V;
    std::vector<Face>& T = *F;
    std::vector<std::vector<int>> vf(static_cast<size_t>(nv));
    for (size_t f = 0; f < T.size(); ++f)
        for (int k = 0; k < 3; ++k)
            vf[static_cast<size_t>(T[f][static_cast<size_t>(k)])].push_back(static_cast<int>(f));
    std::vector<char> face_alive(T.size(), 1), vert_alive(static_cast<size_t>(nv), 1);
    std::vector<int> version(static_cast<size_t>(nv), 0);

    struct Entry {
        double len;
        int u, v, vu, vv;
        bool operator>(const Entry& o) const {
            if (len != o.len) return len > o.len;
            if (u != o.u) return u > o.u;
            return v > o.v;
        }
    };
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    auto push_edges_of = [&](int u) {
        for (const int f : vf[static_cast<size_t>(u)])
            for (int k = 0; k < 3; ++k) {
                const int w = T[static_cast<size_t>(f)][static_cast<size_t>(k)];
                // Each undirected edge once per face: push (u, w) when w follows u in the face.
                if (T[static_cast<size_t>(f)][static_cast<size_t>((k + 2) % 3)] != u) continue;
                const int a = std::min(u, w), b = std::max(u, w);
                queue.push({(P[static_cast<size_t>(a)] - P[static_cast<size_t>(b)]).norm(), a, b,
                            version[static_cast<size_t>(a)], version[static_cast<size_t>(b)]});
            }
    };
    for (int u = 0; u < nv; ++u) push_edges_of(u);

    auto neighbours = [&](int u, std::vector<int>* out) {
        out->clear();
        for (const int f : vf[static_cast<size_t>(u)])
            for (int k = 0; k < 3; ++k) {
                const int w = T[static_cast<size_t>(f)][static_cast<size_t>(k)];
                if (w != u) out->push_back(w);
            }
        std::sort(out->begin(), out->end());
        out->erase(std::unique(out->begin(), out->end()), out->end());
    };

    // Unit surface normals (SDF gradients) at the vertices.
    std::vector<Vector3d> normal(static_cast<size_t>(nv));
    auto surface_normal = [&](const Vector3d& x) {
        Vector3d g = Vector3d::Zero();
        sdf.eval(x, &g);
        return Vector3d(g.normalized());
    };
    parallel_ranges(static_cast<size_t>(nv), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) normal[i] = surface_normal(P[i]);
    });

    const double min_angle = deg(12.0), min_cos = std::cos(deg(40.0));
    const double min_cos_surface = std::cos(deg(60.0));
    int alive = nv;
    std::vector<int> nu, nvv, no, common;
    while (alive > target && !queue.empty()) {
        const Entry e = queue.top();
        queue.pop();
        if (!vert_alive[static_cast<size_t>(e.u)] || !vert_alive[static_cast<size_t>(e.v)] ||
            version[static_cast<size_t>(e.u)] != e.vu || version[static_cast<size_t>(e.v)] != e.vv)
            continue;
        // v is merged into u; a pinned vertex survives in place.
        const bool pin_u = (*pinned)[static_cast<size_t>(e.u)],
                   pin_v = (*pinned)[static_cast<size_t>(e.v)];
        if (pin_u && pin_v) continue;
        const int u = pin_v ? e.v : e.u, v = pin_v ? e.u : e.v;
        // Shared faces and their opposite vertices.
        int shared[2], opp[2], n_shared = 0;
        for (const int f : vf[static_cast<size_t>(u)]) {
            const Face& t = T[static_cast<size_t>(f)];
            if (t[0] != v && t[1] != v && t[2] != v) continue;
            if (n_shared == 2) {
                n_shared = 3;
                break;
            }
            shared[n_shared] = f;
            opp[n_shared] = t[0] + t[1] + t[2] - u - v;
            ++n_shared;
        }
        if (n_shared != 2) continue;
        // Link condition: the common neighbours of u and v are exactly the two opposite vertices.
        neighbours(u, &nu);
        neighbours(v, &nvv);
        common.clear();
        std::set_intersection(nu.begin(), nu.end(), nvv.begin(), nvv.end(),
                              std::back_inserter(common));
        if (common.size() != 2) continue;
        // Valences: u gets deg(u) + deg(v) - 4, each opposite vertex loses one.
        const int new_valence = static_cast<int>(nu.size() + nvv.size()) - 4;
        if (new_valence > 10) continue;
        bool ok = true;
        for (int i = 0; i < 2 && ok; ++i) {
            neighbours(opp[i], &no);
            if (static_cast<int>(no.size()) - 1 < 4) ok = false;
        }
        if (!ok) continue;
        const Vector3d p =
            (pin_u || pin_v)
                ? P[static_cast<size_t>(u)]
                : sdf.project(0.5 * (P[static_cast<size_t>(u)] + P[static_cast<size_t>(v)]), 4,
                              max_step);
        // Geometry of the surviving faces around u and v after the move: no large turn, not
        // thinner than before (or at least min_angle), and facing about like the surface there
        // (a coarse thin tube must not get triangles slicing across it).
        const Vector3d n_p = (pin_u || pin_v) ? normal[static_cast<size_t>(u)] : surface_normal(p);
        for (const int w : {u, v}) {
            for (const int f : vf[static_cast<size_t>(w)]) {
                if (f == shared[0] || f == shared[1]) continue;
                const Face& t = T[static_cast<size_t>(f)];
                Vector3d q[3], o[3], sn = Vector3d::Zero();
                for (int k = 0; k < 3; ++k) {
                    const int x = t[static_cast<size_t>(k)];
                    o[k] = P[static_cast<size_t>(x)];
                    q[k] = (x == w) ? p : o[k];
                    sn += (x == w) ? n_p : normal[static_cast<size_t>(x)];
                }
                const Vector3d n_old = (o[1] - o[0]).cross(o[2] - o[0]);
                const Vector3d n_new = (q[1] - q[0]).cross(q[2] - q[0]);
                const double ln = n_new.norm(), lo = n_old.norm();
                if (ln <= 0.0 || lo <= 0.0 || n_new.dot(n_old) < min_cos * ln * lo ||
                    n_new.dot(sn) < min_cos_surface * ln * sn.norm()) {
                    ok = false;
                    break;
                }
                const double angle = triangle_min_angle(q[0], q[1], q[2]);
                if (angle < min_angle && angle < triangle_min_angle(o[0], o[1], o[2])) {
                    ok = false;
                    break;
                }
            }
            if (!ok) break;
        }
        if (!ok) continue;
        // Apply: drop the shared faces, re-point v's faces to u.
        for (const int f : shared) {
            face_alive[static_cast<size_t>(f)] = 0;
            for (const int w : T[static_cast<size_t>(f)]) {
                auto& l = vf[static_cast<size_t>(w)];
                l.erase(std::remove(l.begin(), l.end(), f), l.end());
            }
        }
        for (const int f : vf[static_cast<size_t>(v)]) {
            for (int& w : T[static_cast<size_t>(f)])
                if (w == v) w = u;
            vf[static_cast<size_t>(u)].push_back(f);
        }
        vf[static_cast<size_t>(v)].clear();
        vert_alive[static_cast<size_t>(v)] = 0;
        P[static_cast<size_t>(u)] = p;
        normal[static_cast<size_t>(u)] = n_p;
        ++version[static_cast<size_t>(u)];
        --alive;
        push_edges_of(u);
    }
    // Compact.
    std::vector<int> remap(static_cast<size_t>(nv), -1);
    std::vector<Vector3d> P2;
    std::vector<char> pinned2;
    P2.reserve(static_cast<size_t>(alive));
    pinned2.reserve(static_cast<size_t>(alive));
    for (int i = 0; i < nv; ++i)
        if (vert_alive[static_cast<size_t>(i)]) {
            remap[static_cast<size_t>(i)] = static_cast<int>(P2.size());
            P2.push_back(P[static_cast<size_t>(i)]);
            pinned2.push_back((*pinned)[static_cast<size_t>(i)]);
        }
    pinned->swap(pinned2);
    std::vector<Face> T2;
    T2.reserve(T.size());
    for (size_t f = 0; f < T.size(); ++f)
        if (face_alive[f])
            T2.push_back({remap[static_cast<size_t>(T[f][0])], remap[static_cast<size_t>(T[f][1])],
                          remap[static_cast<size_t>(T[f][2])]});
    P.swap(P2);
    T.swap(T2);
    return alive;
}

// ------------------------------------------------------------------------------ rest figure

constexpr int kInfluences = 4;             // bones per vertex
constexpr double kWeightSmoothing = 0.09;  // radius of the ball the sharp weights are averaged over

struct RestFigure {
    std::vector<Vector3d> V;
    std::vector<Face> F;
    std::vector<std::array<int, kInfluences>> bone;  ///< per vertex: bones, largest weight first
    std::vector<std::array<double, kInfluences>> weight;
    std::vector<int> tip_vertex;
};

/// Skinning weights at rest position p. Sharp weights w_b ~ dn_b^-12, where dn_b is the smallest
/// normalized distance (distance to the axis / local radius, 1 on the capsule surface) over bone
/// b's capsules, are averaged over a ball of radius kWeightSmoothing around p (19 fixed samples),
/// which widens the transitions at the joints to about the ball's diameter (sharper transitions
/// fold the skin at large joint angles; weights decaying slowly everywhere bend the limbs). The
/// kInfluences largest weights are kept and normalized.
void skin_weights(const Body& body, const Vector3d& p, std::array<int, kInfluences>* bones,
                  std::array<double, kInfluences>* weights) {
    static const std::vector<Vector3d> offsets = [] {
        std::vector<Vector3d> o;
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j)
                for (int k = -1; k <= 1; ++k)
                    if (i * i + j * j + k * k <= 2)
                        o.emplace_back(Vector3d(i, j, k) * (std::sqrt(0.5) * kWeightSmoothing));
        return o;
    }();
    // Bounds of each bone's normalized distance over the ball. Bones 4x farther than the best
    // bound everywhere in the ball would get relative weights < 4^-12 ~ 6e-8: they are left out.
    double lo[kNumBones], hi[kNumBones];
    std::fill(lo, lo + kNumBones, std::numeric_limits<double>::infinity());
    std::fill(hi, hi + kNumBones, std::numeric_limits<double>::infinity());
    for (const Capsule& c : body.caps) {
        const Vector3d ab = c.b - c.a;
        const double t = std::clamp((p - c.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        const double d = (p - (c.a + t * ab)).norm();
        const double r_lo = std::min(c.ra, c.rb), r_hi = std::max(c.ra, c.rb);
        lo[c.bone] = std::min(lo[c.bone], std::max(0.0, d - kWeightSmoothing) / r_hi);
        hi[c.bone] = std::min(hi[c.bone], (d + kWeightSmoothing) / r_lo);
    }
    const double cutoff = 4.0 * *std::min_element(hi, hi + kNumBones);
    const Capsule* caps[kMaxCapsules];
    int n_caps = 0;
    for (const Capsule& c : body.caps)
        if (lo[c.bone] < cutoff) caps[n_caps++] = &c;

    double acc[kNumBones] = {};
    for (const Vector3d& o : offsets) {
        const Vector3d q = p + o;
        double dn[kNumBones];
        std::fill(dn, dn + kNumBones, std::numeric_limits<double>::infinity());
        for (int i = 0; i < n_caps; ++i)
            dn[caps[i]->bone] =
                std::min(dn[caps[i]->bone], capsule_normalized_distance(*caps[i], q));
        double w[kNumBones] = {};
        double sum = 0.0;
        for (int b = 0; b < kNumBones; ++b) {
            if (!(dn[b] < std::numeric_limits<double>::infinity())) continue;
            const double d2 = std::max(dn[b], 1e-3) * std::max(dn[b], 1e-3);
            const double d4 = d2 * d2;
            w[b] = 1.0 / (d4 * d4 * d4);
            sum += w[b];
        }
        for (int b = 0; b < kNumBones; ++b) acc[b] += w[b] / sum;
    }
    std::array<std::pair<double, int>, kNumBones> w;
    for (int b = 0; b < kNumBones; ++b) w[static_cast<size_t>(b)] = {acc[b], b};
    std::partial_sort(w.begin(), w.begin() + kInfluences, w.end(),
                      [](const auto& x, const auto& y) {
                          return x.first > y.first || (x.first == y.first && x.second < y.second);
                      });
    double sum = 0.0;
    for (int i = 0; i < kInfluences; ++i) sum += w[static_cast<size_t>(i)].first;
    for (int i = 0; i < kInfluences; ++i) {
        (*bones)[static_cast<size_t>(i)] = w[static_cast<size_t>(i)].second;
        (*weights)[static_cast<size_t>(i)] = w[static_cast<size_t>(i)].first / sum;
    }
}

/// Deterministic grid shift for retry `attempt` (quasi-random, attempt 0 = cell centre offset).
Vector3d grid_shift(int attempt) {
    const double g1 = 0.8191725133961645, g2 = 0.6710436067037893, g3 = 0.5497004779019703;
    return Vector3d(std::fmod(0.5 + g1 * attempt, 1.0), std::fmod(0.5 + g2 * attempt, 1.0),
                    std::fmod(0.5 + g3 * attempt, 1.0));
}

std::shared_ptr<RestFigure> build_rest_figure(int target) {
    const Body& body = the_body();
    const BodySdf sdf(body);
    // Calibrate: the number of surface cells scales like 1 / h^2.
    const double h_cal = 0.03;
    long n_cal = 0;
    surface_nets(sdf, body.box, h_cal, grid_shift(0), true, &n_cal, nullptr, nullptr, nullptr);
    const double c_cal = static_cast<double>(n_cal) * h_cal * h_cal;
    // Coarsest spacing used for extraction (the thinnest tube, radius 0.04, gets ~4 cells across);
    // coarser targets are reached by decimation. Aim a little above the target, then decimate.
    const double h_max = 0.55 * body.min_radius;
    double h = std::min(h_max, std::sqrt(c_cal / (1.06 * target)));
    const size_t n_tips = body.tips.size();

    std::string why;
    for (int attempt = 0; attempt < 12; ++attempt) {
        std::vector<Vector3d> V;
        std::vector<Face> F;
        if (!surface_nets(sdf, body.box, h, grid_shift(attempt), false, nullptr, &V, &F, &why))
            continue;
        if (static_cast<int>(V.size()) < target) {
            // Spacing too coarse (the calibration is approximate): refine and retry.
            h *= std::sqrt(static_cast<double>(V.size()) / (1.08 * target));
            why = "too few vertices";
            continue;
        }
        if (!check_closed_sphere(static_cast<int>(V.size()), F, &why)) continue;
        parallel_ranges(V.size(), [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) V[i] = sdf.project(V[i], 3, h);
        });
        std::vector<char> pinned(V.size(), 0);
        relax(sdf, &V, F, pinned, 2, 0.6, h);
        // Put a vertex exactly on every limb tip and keep it there (coarse meshes would otherwise
        // round the tips off).
        for (const Vector3d& tip : body.tips) {
            size_t best = 0;
            for (size_t i = 1; i < V.size(); ++i)
                if ((V[i] - tip).squaredNorm() < (V[best] - tip).squaredNorm()) best = i;
            V[best] = tip;
            pinned[best] = 1;
        }
        if (static_cast<int>(V.size()) > target) {
            const int reached = decimate(sdf, &V, &F, &pinned, target, 4.0 * h);
            if (reached != target) {
                why = "decimation stalled at " + std::to_string(reached) + " vertices";
                continue;
            }
        }
        relax(sdf, &V, F, pinned, 4, 0.6, std::sqrt(c_cal / target));
        if (!check_closed_sphere(static_cast<int>(V.size()), F, &why)) continue;
        if (!check_quality(sdf, V, F, deg(10.0), &why)) continue;

        auto rest = std::make_shared<RestFigure>();
        rest->V = std::move(V);
        rest->F = std::move(F);
        const size_t n = rest->V.size();
        rest->bone.resize(n);
        rest->weight.resize(n);
        parallel_ranges(n, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i)
                skin_weights(body, rest->V[i], &rest->bone[i], &rest->weight[i]);
        });
        rest->tip_vertex.assign(n_tips, -1);
        for (size_t t = 0; t < n_tips; ++t)
            for (size_t i = 0; i < n; ++i)
                if (pinned[i] && rest->V[i] == body.tips[t])
                    rest->tip_vertex[t] = static_cast<int>(i);
        if (std::count(rest->tip_vertex.begin(), rest->tip_vertex.end(), -1) != 0) {
            why = "lost a limb tip vertex";
            continue;
        }
        return rest;
    }
    throw std::runtime_error("make_figure: could not extract a valid mesh for " +
                             std::to_string(target) + " vertices (" + why + ")");
}

std::shared_ptr<const RestFigure> rest_figure(int target) {
    static std::mutex mutex;
    static std::list<std::pair<int, std::shared_ptr<const RestFigure>>> cache;  // most recent first
    constexpr size_t kCacheSize = 4;
    std::lock_guard<std::mutex> lock(mutex);
    for (auto it = cache.begin(); it != cache.end(); ++it)
        if (it->first == target) {
            cache.splice(cache.begin(), cache, it);
            return cache.front().second;
        }
    std::shared_ptr<const RestFigure> rest = build_rest_figure(target);
    cache.emplace_front(target, rest);
    if (cache.size() > kCacheSize) cache.pop_back();
    return rest;
}

// ----------------------------------------------------------------------------------- posing

Matrix3d rot(const Vector3d& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// Local joint rotations (rest frame) for a pose; right limbs are the mirror images of left ones.
std::array<Matrix3d, kNumBones> joint_rotations(const FigurePose& p) {
    const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
    const Matrix3d M = Vector3d(-1, 1, 1).asDiagonal();
    std::array<Matrix3d, kNumBones> R;
    R.fill(Matrix3d::Identity());
    R[kHead] = rot(Z, p.head_yaw) * rot(X, p.head_pitch);
    // A limb's upper and lower rotations; right limbs mirror the left ones' (M R M).
    auto limb = [&](Matrix3d ru, Matrix3d rl, int upper, int lower, bool right) {
        if (right) {
            ru = M * ru * M;
            rl = M * rl * M;
        }
        R[static_cast<size_t>(upper)] = ru;
        R[static_cast<size_t>(lower)] = rl;
    };
    auto arm = [&](const ArmPose& a, int upper, int lower, bool right) {
        limb(rot(Z, -a.shoulder_forward) * rot(Y, a.shoulder_down), rot(Z, -a.elbow_bend), upper, lower, right);
    };
    auto leg = [&](const LegPose& l, int upper, int lower, bool right) {
        limb(rot(X, -l.hip_forward) * rot(Y, -l.hip_out), rot(X, l.knee_bend), upper, lower, right);
    };
    arm(p.left_arm, kLUpperArm, kLLowerArm, false);
    arm(p.right_arm, kRUpperArm, kRLowerArm, true);
    leg(p.left_leg, kLUpperLeg, kLLowerLeg, false);
    leg(p.right_leg, kRUpperLeg, kRLowerLeg, true);
    R[kTail1] = rot(Z, -p.tail_swing) * rot(X, 0.5 * p.tail_curl);
    R[kTail2] = rot(X, p.tail_curl);
    R[kTail3] = rot(X, p.tail_curl);
    return R;
}

struct Rigid {
    Matrix3d R = Matrix3d::Identity();
    Vector3d t = Vector3d::Zero();
};

std::array<Rigid, kNumBones> bone_transforms(const Body& body, const FigurePose& pose) {
    const std::array<Matrix3d, kNumBones> local = joint_rotations(pose);
    std::array<Rigid, kNumBones> G;
    for (int b = 0; b < kNumBones; ++b) {
        const Bone& bone = body.bones[static_cast<size_t>(b)];
        const Matrix3d& r = local[static_cast<size_t>(b)];
        Rigid l;  // x -> j + r (x - j)
        l.R = r;
        l.t = bone.joint - r * bone.joint;
        if (bone.parent < 0) {
            G[static_cast<size_t>(b)] = l;
        } else {
            const Rigid& p = G[static_cast<size_t>(bone.parent)];
            G[static_cast<size_t>(b)].R = p.R * l.R;
            G[static_cast<size_t>(b)].t = p.R * l.t + p.t;
        }
    }
    return G;
}

Vector3d skin(const std::array<Rigid, kNumBones>& G, const Vector3d& p,
              const std::array<int, kInfluences>& bones, const std::array<double, kInfluences>& w) {
    Vector3d q = Vector3d::Zero();
    for (int i = 0; i < kInfluences; ++i) {
        const Rigid& g = G[static_cast<size_t>(bones[static_cast<size_t>(i)])];
        q += w[static_cast<size_t>(i)] * (g.R * p + g.t);
    }
    return q;
}

// Deterministic uniform double in [lo, hi) from mt19937 (whose output is fully specified).
double uniform(std::mt19937& rng, double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0);
}

}  // namespace

FigurePose figure_pose(int pose_id) {
    if (pose_id < 0) throw std::invalid_argument("figure_pose: pose_id must be >= 0");
    FigurePose p;
    switch (pose_id) {
        case 0:  // rest
            break;
        case 1:  // arms down, relaxed
            p.left_arm = {deg(65), deg(10), deg(20)};
            p.right_arm = {deg(65), deg(10), deg(20)};
            p.left_leg = {0.0, deg(-6), deg(5)};
            p.right_leg = {0.0, deg(-6), deg(5)};
            p.head_pitch = deg(15);
            p.tail_curl = deg(10);
            break;
        case 2:  // arms up with bent elbows, left knee raised, tail curled up
            p.left_arm = {deg(-40), deg(10), deg(70)};
            p.right_arm = {deg(-35), deg(-10), deg(50)};
            p.left_leg = {deg(40), 0.0, deg(60)};
            p.right_leg = {deg(-5), deg(5), deg(5)};
            p.head_yaw = deg(-30);
            p.tail_curl = deg(45);
            break;
        case 3:  // walking stride, head turned, tail swung
            p.left_arm = {deg(55), deg(35), deg(30)};
            p.right_arm = {deg(55), deg(-25), deg(10)};
            p.left_leg = {deg(30), deg(-5), deg(25)};
            p.right_leg = {deg(-20), 0.0, deg(10)};
            p.head_yaw = deg(40);
            p.tail_swing = deg(30);
            p.tail_curl = deg(20);
            break;
        case 4:  // half crouch reaching forwards, looking up
            p.left_arm = {deg(35), deg(45), deg(70)};
            p.right_arm = {deg(35), deg(45), deg(70)};
            p.left_leg = {deg(45), deg(10), deg(70)};
            p.right_leg = {deg(45), deg(10), deg(70)};
            p.head_pitch = deg(-20);
            p.tail_curl = deg(15);
            break;
        case 5:  // legs crossed, left arm up, right forearm across the front
            p.left_arm = {deg(-60), 0.0, deg(30)};
            p.right_arm = {deg(40), deg(40), deg(90)};
            p.left_leg = {deg(20), deg(-25), deg(10)};
            p.right_leg = {deg(-12), deg(-20), deg(10)};
            p.head_pitch = deg(20);
            p.head_yaw = deg(-45);
            p.tail_swing = deg(-40);
            p.tail_curl = deg(50);
            break;
        default: {
            std::mt19937 rng(static_cast<std::uint32_t>(pose_id));
            auto arm = [&](ArmPose* a) {
                a->shoulder_down = uniform(rng, -0.7, 1.1);
                a->shoulder_forward = uniform(rng, -0.4, 0.7);
                a->elbow_bend = uniform(rng, 0.0, 1.3);
            };
            auto leg = [&](LegPose* l) {
                l->hip_forward = uniform(rng, -0.3, 0.6);
                l->hip_out = uniform(rng, -0.1, 0.35);
                l->knee_bend = uniform(rng, 0.0, 1.0);
            };
            arm(&p.left_arm);
            arm(&p.right_arm);
            leg(&p.left_leg);
            leg(&p.right_leg);
            p.head_yaw = uniform(rng, -0.8, 0.8);
            p.head_pitch = uniform(rng, -0.3, 0.4);
            p.tail_swing = uniform(rng, -0.4, 0.4);
            p.tail_curl = uniform(rng, -0.2, 0.5);
            break;
        }
    }
    return p;
}

Figure make_figure(int target_vertices, const FigurePose& pose) {
    return make_figure(target_vertices, pose, FigureProportions());
}

std::vector<std::string> figure_class_names() {
    return {"standard", "long-arms", "short-legs", "long-tail", "stocky", "long-neck"};
}

FigureProportions figure_class(const std::string& name) {
    FigureProportions p;
    if (name == "standard") return p;
    if (name == "long-arms") {
        p.arm_length = 1.4;
    } else if (name == "short-legs") {
        p.leg_length = 0.65;
    } else if (name == "long-tail") {
        p.tail_length = 1.7;
    } else if (name == "stocky") {
        p.limb_girth = 1.45;
        p.torso_girth = 1.35;
        p.leg_length = 0.85;
        p.arm_length = 0.85;
    } else if (name == "long-neck") {
        p.neck_length = 1.5;
        p.torso_length = 1.15;
    } else {
        std::string known;
        for (const auto& n : figure_class_names()) known += (known.empty() ? "" : ", ") + n;
        throw std::invalid_argument("unknown figure class '" + name + "' (known: " + known + ")");
    }
    return p;
}

namespace {

/// Affine map x -> A x + c.
struct Affine {
    Matrix3d A = Matrix3d::Identity();
    Vector3d c = Vector3d::Zero();
    Vector3d operator()(const Vector3d& x) const { return A * x + c; }
};

/// Per-bone shape maps of FigureProportions (parents before children): bone b maps x to
/// S_parent(j_b) + M_b (x - j_b), M_b = length d d^T + girth (I - d d^T), d = the bone's axis.
std::array<Affine, kNumBones> shape_maps(const Body& body, const FigureProportions& p) {
    const Vector3d Z = Vector3d::UnitZ();
    std::array<Vector3d, kNumBones> axis;
    axis.fill(Z);
    std::array<double, kNumBones> length, girth;
    length.fill(1.0);
    girth.fill(1.0);
    auto set = [&](int b, const Vector3d& to, double l, double g) {
        axis[static_cast<size_t>(b)] = (to - body.bones[static_cast<size_t>(b)].joint).normalized();
        length[static_cast<size_t>(b)] = l;
        girth[static_cast<size_t>(b)] = g;
    };
    const auto joint = [&](int b) { return body.bones[static_cast<size_t>(b)].joint; };
    length[kRoot] = p.torso_length;
    girth[kRoot] = p.torso_girth;
    set(kHead, joint(kHead) + Z, p.neck_length, 1.0);
    set(kLUpperArm, joint(kLLowerArm), p.arm_length, p.limb_girth);
    set(kLLowerArm, body.tips[1], p.arm_length, p.limb_girth);
    set(kRUpperArm, joint(kRLowerArm), p.arm_length, p.limb_girth);
    set(kRLowerArm, body.tips[2], p.arm_length, p.limb_girth);
    set(kLUpperLeg, joint(kLLowerLeg), p.leg_length, p.limb_girth);
    set(kLLowerLeg, body.tips[3], p.leg_length, p.limb_girth);
    set(kRUpperLeg, joint(kRLowerLeg), p.leg_length, p.limb_girth);
    set(kRLowerLeg, body.tips[4], p.leg_length, p.limb_girth);
    set(kTail1, joint(kTail2), p.tail_length, p.limb_girth);
    set(kTail2, joint(kTail3), p.tail_length, p.limb_girth);
    set(kTail3, body.tips[5], p.tail_length, p.limb_girth);
    std::array<Affine, kNumBones> S;
    for (int b = 0; b < kNumBones; ++b) {
        const size_t k = static_cast<size_t>(b);
        const Vector3d& d = axis[k];
        const Matrix3d M = length[k] * d * d.transpose() + girth[k] * (Matrix3d::Identity() - d * d.transpose());
        const Vector3d j = body.bones[k].joint;
        const Vector3d moved = body.bones[k].parent < 0 ? j : S[static_cast<size_t>(body.bones[k].parent)](j);
        S[k].A = M;
        S[k].c = moved - M * j;
    }
    return S;
}

}  // namespace

Figure make_figure(int target_vertices, const FigurePose& pose, const FigureProportions& proportions) {
    if (target_vertices < 300 || target_vertices > 1000000)
        throw std::invalid_argument("make_figure: target_vertices must be in [300, 1000000]");
    for (double f : {proportions.arm_length, proportions.leg_length, proportions.tail_length, proportions.neck_length,
                     proportions.torso_length, proportions.limb_girth, proportions.torso_girth})
        if (!(f >= 0.5 && f <= 2.0)) throw std::invalid_argument("make_figure: proportions must lie in [0.5, 2]");
    const Body& standard = the_body();
    const std::shared_ptr<const RestFigure> rest = rest_figure(target_vertices);
    const std::array<Affine, kNumBones> S = shape_maps(standard, proportions);
    // The body with its joints where the shape maps put them (the pose rotates about those).
    Body body = standard;
    for (int b = 0; b < kNumBones; ++b) {
        Bone& bone = body.bones[static_cast<size_t>(b)];
        bone.joint = bone.parent < 0 ? bone.joint : S[static_cast<size_t>(bone.parent)](bone.joint);
    }
    const std::array<Rigid, kNumBones> G = bone_transforms(body, pose);

    const bool standard_shape = proportions.arm_length == 1 && proportions.leg_length == 1 &&
                                proportions.tail_length == 1 && proportions.neck_length == 1 &&
                                proportions.torso_length == 1 && proportions.limb_girth == 1 &&
                                proportions.torso_girth == 1;
    Figure fig;
    std::vector<Vector3d> posed(rest->V.size());
    for (size_t i = 0; i < rest->V.size(); ++i) {
        if (standard_shape) {  // exactly the standard figure (no round-off from the identity maps)
            posed[i] = skin(G, rest->V[i], rest->bone[i], rest->weight[i]);
            continue;
        }
        Vector3d shaped = Vector3d::Zero();
        for (int k = 0; k < kInfluences; ++k)
            shaped += rest->weight[i][static_cast<size_t>(k)] *
                      S[static_cast<size_t>(rest->bone[i][static_cast<size_t>(k)])](rest->V[i]);
        posed[i] = skin(G, shaped, rest->bone[i], rest->weight[i]);
    }
    fig.mesh = to_trimesh(posed, rest->F);
    for (size_t t = 0; t < body.tips.size(); ++t)
        fig.limb_tips.push_back(posed[static_cast<size_t>(rest->tip_vertex[t])]);
    fig.limb_names = body.tip_names;
    fig.limb_radius = body.tip_radius;
    const double limb_girth[] = {1.0, proportions.limb_girth, proportions.limb_girth, proportions.limb_girth,
                                 proportions.limb_girth, proportions.limb_girth};
    for (size_t t = 0; t < fig.limb_radius.size() && t < 6; ++t) fig.limb_radius[t] *= limb_girth[t];
    fig.limb_tip_vertex = rest->tip_vertex;
    return fig;
}

}  // namespace canonform::procedural
