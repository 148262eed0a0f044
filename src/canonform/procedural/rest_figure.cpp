// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the rest figure: extraction, coarsening, skinning weights. See rest_figure.h.
#include "canonform/procedural/rest_figure.h"
#include "canonform/procedural/decimation.h"
#include "canonform/procedural/mesh_building.h"
#include "canonform/procedural/mesh_checks.h"
#include "canonform/procedural/relaxation.h"
#include "canonform/procedural/surface_nets.h"
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
            dn[caps[i]->bone] = std::min(dn[caps[i]->bone], capsule_normalized_distance(*caps[i], q));
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
    std::partial_sort(w.begin(), w.begin() + kInfluences, w.end(), [](const auto& x, const auto& y) {
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
        if (!surface_nets(sdf, body.box, h, grid_shift(attempt), false, nullptr, &V, &F, &why)) continue;
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
                if (pinned[i] && rest->V[i] == body.tips[t]) rest->tip_vertex[t] = static_cast<int>(i);
        if (std::count(rest->tip_vertex.begin(), rest->tip_vertex.end(), -1) != 0) {
            why = "lost a limb tip vertex";
            continue;
        }
        return rest;
    }
    throw std::runtime_error("make_figure: could not extract a valid mesh for " + std::to_string(target) +
                             " vertices (" + why + ")");
}
}  // namespace

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

}  // namespace detail
}  // namespace canonform::procedural
