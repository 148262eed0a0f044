// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: tangential relaxation on the zero set. See relaxation.h.
#include "canonform/procedural/relaxation.h"
#include "canonform/procedural/mesh_building.h"
#include "canonform/procedural/mesh_checks.h"
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

void relax(const BodySdf& sdf, std::vector<Vector3d>* V, const std::vector<Face>& F,
           const std::vector<char>& pinned, int iterations, double lambda, double max_step) {
    const size_t nv = V->size();
    const numerics::VertexAdjacency adjacency =
        numerics::vertex_adjacency(static_cast<int>(nv), surface::unique_edges(to_trimesh({}, F).F));
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
                for (int i = b; i < e; ++i) c += (*V)[static_cast<size_t>(nb[static_cast<size_t>(i)])];
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
                    bad[i] =
                        n_new.dot(n_old) <= 0.2 * ln * n_old.norm() || n_new.dot(sn) <= 0.2 * ln * sn.norm();
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

}  // namespace detail
}  // namespace canonform::procedural
