// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: shortest-edge collapses on the zero set. See decimation.h.
#include "canonform/procedural/decimation.h"
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

int decimate(const BodySdf& sdf, std::vector<Vector3d>* V, std::vector<Face>* F, std::vector<char>* pinned,
             int target, double max_step) {
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
        const bool pin_u = (*pinned)[static_cast<size_t>(e.u)], pin_v = (*pinned)[static_cast<size_t>(e.v)];
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
        std::set_intersection(nu.begin(), nu.end(), nvv.begin(), nvv.end(), std::back_inserter(common));
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
                : sdf.project(0.5 * (P[static_cast<size_t>(u)] + P[static_cast<size_t>(v)]), 4, max_step);
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

}  // namespace detail
}  // namespace canonform::procedural
