// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/feature_points.h"

#include "canonform/common/errors.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace canonform::surface {

int sqrt_count(int n) {
    int s = static_cast<int>(std::sqrt(static_cast<double>(n)));
    while (static_cast<long long>(s) * s < n) ++s;
    while (s > 0 && static_cast<long long>(s - 1) * (s - 1) >= n) --s;
    return s;
}

std::vector<int> local_maxima(const numerics::VertexAdjacency& adj, const Eigen::VectorXd& phi, int ring) {
    if (ring < 1) throw InputError("the ring size of a local maximum must be at least 1");
    const int n = adj.num_vertices();
    std::vector<int> maxima;
    std::vector<int> stamp(static_cast<size_t>(n), -1), frontier, next;
    for (int v = 0; v < n; ++v) {
        // Cheap 1-ring test first; the k-ring search only for the survivors.
        bool is_max = true;
        for (int k = adj.offsets[static_cast<size_t>(v)];
             k < adj.offsets[static_cast<size_t>(v) + 1] && is_max; ++k)
            is_max = phi(v) > phi(adj.neighbors[static_cast<size_t>(k)]);
        if (!is_max) continue;
        stamp[static_cast<size_t>(v)] = v;
        frontier.assign(1, v);
        for (int depth = 0; depth < ring && is_max && !frontier.empty(); ++depth) {
            next.clear();
            for (int u : frontier) {
                for (int k = adj.offsets[static_cast<size_t>(u)]; k < adj.offsets[static_cast<size_t>(u) + 1];
                     ++k) {
                    const int w = adj.neighbors[static_cast<size_t>(k)];
                    if (stamp[static_cast<size_t>(w)] == v) continue;
                    stamp[static_cast<size_t>(w)] = v;
                    if (!(phi(v) > phi(w))) {
                        is_max = false;
                        break;
                    }
                    next.push_back(w);
                }
                if (!is_max) break;
            }
            frontier.swap(next);
        }
        if (is_max) maxima.push_back(v);
    }
    return maxima;
}

ParameterSet<FeaturePointOptions> feature_point_parameters(const FeaturePointOptions& defaults) {
    ParameterSet<FeaturePointOptions> s(defaults);
    s.add(
        Parameter::integer("ring", 1, 10)
            .label("Ring size (k)")
            .help("k of the k-ring in which a feature point is a strict maximum of the conformal factor (the "
                  "paper uses 2)"),
        &FeaturePointOptions::ring);
    s.add(
        Parameter::choice("fill", {"none", "random"})  // FeatureFill's enumerators, in order
            .label("Fill")
            .help(
                "none: local maxima only (variant N); random: add seeded random vertices up to ceil(sqrt(N)) "
                "(variant A)"),
        &FeaturePointOptions::fill);
    s.add(Parameter::integer("seed", 0, 2147483647)
              .label("Random seed")
              .help("seed of the random fill (variant A's extra feature points)"),
          &FeaturePointOptions::seed);
    return s;
}

namespace {

/// Unbiased draw in [0, bound) from a 64-bit engine (rejection sampling; portable, unlike
/// std::uniform_int_distribution whose algorithm is implementation defined).
std::uint64_t bounded(std::mt19937_64& rng, std::uint64_t bound) {
    const std::uint64_t limit = ~std::uint64_t(0) - (~std::uint64_t(0) % bound);
    std::uint64_t x;
    do x = rng();
    while (x >= limit);
    return x % bound;
}

}  // namespace

FeaturePoints feature_points(const numerics::VertexAdjacency& adj, const Eigen::VectorXd& phi,
                             const FeaturePointOptions& options) {
    const int n = adj.num_vertices();
    if (phi.size() != n) throw InputError("feature points: one conformal factor per vertex is needed");
    if (!phi.allFinite()) throw NumericalError("feature points: the conformal factor has non-finite values");
    if (options.count > n)
        throw InputError("feature points: " + std::to_string(options.count) +
                         " asked for, but the mesh has only " + std::to_string(n) + " vertices");
    const int target = options.count < 0 ? sqrt_count(n) : options.count;

    FeaturePoints fp;
    std::vector<int> maxima = local_maxima(adj, phi, options.ring);
    fp.total_maxima = static_cast<int>(maxima.size());
    std::sort(maxima.begin(), maxima.end(),
              [&](int a, int b) { return phi(a) > phi(b) || (phi(a) == phi(b) && a < b); });
    if (static_cast<int>(maxima.size()) > target) maxima.resize(static_cast<size_t>(target));
    fp.indices = maxima;
    fp.num_maxima = static_cast<int>(maxima.size());

    if (options.fill == FeatureFill::Random && fp.num_maxima < target) {
        std::vector<char> chosen(static_cast<size_t>(n), 0);
        for (int v : maxima) chosen[static_cast<size_t>(v)] = 1;
        std::vector<int> pool;
        pool.reserve(static_cast<size_t>(n));
        for (int v = 0; v < n; ++v)
            if (!chosen[static_cast<size_t>(v)]) pool.push_back(v);
        std::sort(pool.begin(), pool.end(),
                  [&](int a, int b) { return phi(a) < phi(b) || (phi(a) == phi(b) && a < b); });
        std::mt19937_64 rng(options.seed);
        const int need = target - fp.num_maxima;
        for (int k = 0; k < need; ++k) {  // partial Fisher-Yates
            const auto j = static_cast<size_t>(k) + bounded(rng, pool.size() - static_cast<size_t>(k));
            std::swap(pool[static_cast<size_t>(k)], pool[j]);
            fp.indices.push_back(pool[static_cast<size_t>(k)]);
        }
        fp.num_random = need;
    }
    return fp;
}

FeaturePoints feature_points(const Eigen::MatrixXi& F, const Eigen::VectorXd& phi,
                             const FeaturePointOptions& options) {
    const numerics::VertexAdjacency adj =
        numerics::vertex_adjacency(static_cast<int>(phi.size()), unique_edges(F));
    return feature_points(adj, phi, options);
}

}  // namespace canonform::surface
