// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the procedural figure's body (private to procedural/). Its rest pose is the zero set
// of a signed distance function: tapered capsules, hard union within a limb, polynomial smooth-min
// between body parts; 13 bones carry the capsules for skinning.
#pragma once

#include "canonform/procedural/mesh_building.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace canonform::procedural {
namespace detail {

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
inline double capsule_eval(const Capsule& c, const Vector3d& p, Vector3d* grad) {
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
inline double capsule_normalized_distance(const Capsule& c, const Vector3d& p) {
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

/// The standard body (built once).
const Body& the_body();

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
    Vector3d project(Vector3d p, int steps, double max_step, const int* ids = nullptr, int n_ids = 0,
                     Vector3d* last_grad = nullptr) const {
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

}  // namespace detail
}  // namespace canonform::procedural
