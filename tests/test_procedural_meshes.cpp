// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of core/procedural_meshes: icosphere, torus, disc and the articulated figure.
//
// The topology and geometry checks below are written independently of the library's own
// validation (which is internal to procedural_meshes.cpp).
//
// Build times of make_figure measured on the development machine (2-vCPU AMD EPYC VM, g++ 12 -O2,
// rest mesh not cached, wall clock, exact vertex counts): 2k vertices 0.15 s, 10k 0.19 s,
// 50k 0.70 s, 200k 2.65 s, 300k 3.9 s (1M: 15 s, 380 MB). Timing is not tested.
#include "canonform/procedural/procedural_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace {

using namespace canonform::procedural;
using canonform::Mesh;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

Vector3d vtx(const Mesh& m, int i) {
    return m.V.row(i).transpose();
}

/// Combinatorial summary of a triangle mesh.
struct Topology {
    bool oriented_manifold = true;  ///< every edge: 1 or 2 faces, opposite orientation if 2
    bool fans_are_discs = true;     ///< each vertex's faces form one fan (closed or open)
    bool all_vertices_used = true;
    int edges = 0;
    int boundary_edges = 0;
    int boundary_loops = 0;
    int components = 0;
    int euler = 0;
    std::string problem;
};

Topology topology(const Mesh& m) {
    Topology t;
    const int nv = static_cast<int>(m.V.rows()), nf = static_cast<int>(m.F.rows());
    std::map<std::pair<int, int>, int> directed;  // (a, b) -> number of faces using a -> b
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) ++directed[{m.F(f, k), m.F(f, (k + 1) % 3)}];
    std::set<std::pair<int, int>> undirected;
    std::map<int, int> boundary_next;  // boundary edge a -> b, keyed by a
    for (const auto& [e, count] : directed) {
        undirected.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
        if (count != 1) {
            t.oriented_manifold = false;
            t.problem = "directed edge used by " + std::to_string(count) + " faces";
        }
        if (directed.count({e.second, e.first}) == 0) {
            ++t.boundary_edges;
            if (boundary_next.count(e.first)) {
                t.oriented_manifold = false;
                t.problem = "two boundary edges leave one vertex";
            }
            boundary_next[e.first] = e.second;
        }
    }
    t.edges = static_cast<int>(undirected.size());
    t.euler = nv - t.edges + nf;
    // Boundary loops.
    std::set<int> seen;
    for (const auto& [start, next] : boundary_next) {
        if (seen.count(start)) continue;
        ++t.boundary_loops;
        int v = start;
        while (!seen.count(v) && boundary_next.count(v)) {
            seen.insert(v);
            v = boundary_next[v];
        }
    }
    // Fans: at v, faces (v, a, b) link a -> b; one chain or one cycle must cover them all.
    std::vector<std::vector<std::pair<int, int>>> fan(static_cast<size_t>(nv));
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k)
            fan[static_cast<size_t>(m.F(f, k))].push_back({m.F(f, (k + 1) % 3), m.F(f, (k + 2) % 3)});
    for (int v = 0; v < nv; ++v) {
        const auto& fv = fan[static_cast<size_t>(v)];
        if (fv.empty()) {
            t.all_vertices_used = false;
            continue;
        }
        std::map<int, int> next;
        std::set<int> targets;
        for (const auto& [a, b] : fv) {
            next[a] = b;
            targets.insert(b);
        }
        // Start at a fan end if the vertex is on the boundary, else anywhere.
        int start = fv.front().first;
        for (const auto& [a, b] : fv)
            if (!targets.count(a)) start = a;
        int steps = 0, cur = start;
        while (next.count(cur) && steps <= static_cast<int>(fv.size())) {
            cur = next[cur];
            ++steps;
            if (cur == start) break;
        }
        if (steps != static_cast<int>(fv.size()) || next.size() != fv.size()) {
            t.fans_are_discs = false;
            t.problem = "vertex " + std::to_string(v) + " is not a single fan";
        }
    }
    // Connected components (union-find).
    std::vector<int> parent(static_cast<size_t>(nv));
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
        while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)];
        return x;
    };
    for (const auto& e : undirected) parent[static_cast<size_t>(find(e.first))] = find(e.second);
    for (int v = 0; v < nv; ++v)
        if (find(v) == v) ++t.components;
    return t;
}

double signed_volume(const Mesh& m) {
    double vol = 0.0;
    for (int f = 0; f < m.F.rows(); ++f)
        vol += vtx(m, m.F(f, 0)).dot(vtx(m, m.F(f, 1)).cross(vtx(m, m.F(f, 2)))) / 6.0;
    return vol;
}

double total_area(const Mesh& m) {
    double a = 0.0;
    for (int f = 0; f < m.F.rows(); ++f)
        a +=
            0.5 * (vtx(m, m.F(f, 1)) - vtx(m, m.F(f, 0))).cross(vtx(m, m.F(f, 2)) - vtx(m, m.F(f, 0))).norm();
    return a;
}

/// Smallest triangle area and smallest corner angle (radians).
std::pair<double, double> min_area_and_angle(const Mesh& m) {
    double min_area = 1e300, min_angle = 1e300;
    for (int f = 0; f < m.F.rows(); ++f) {
        const Vector3d p[3] = {vtx(m, m.F(f, 0)), vtx(m, m.F(f, 1)), vtx(m, m.F(f, 2))};
        min_area = std::min(min_area, 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm());
        for (int k = 0; k < 3; ++k) {
            const Vector3d u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
            min_angle = std::min(min_angle, std::atan2(u.cross(v).norm(), u.dot(v)));
        }
    }
    return {min_area, min_angle};
}

/// Does segment pq cross triangle abc (proper crossing of the plane, inside the triangle)?
bool segment_crosses_triangle(const Vector3d& p, const Vector3d& q, const Vector3d& a, const Vector3d& b,
                              const Vector3d& c) {
    const Vector3d n = (b - a).cross(c - a);
    const double dp = n.dot(p - a), dq = n.dot(q - a);
    if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq) return false;
    const Vector3d x = p + (dp / (dp - dq)) * (q - p);
    const double s1 = n.dot((b - a).cross(x - a)), s2 = n.dot((c - b).cross(x - b)),
                 s3 = n.dot((a - c).cross(x - c));
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Number of pairs of triangles without a common vertex that intersect (uniform grid broad phase).
long self_intersections(const Mesh& m) {
    const int nf = static_cast<int>(m.F.rows());
    const Vector3d lo = m.V.colwise().minCoeff().transpose();
    double mean_edge = 0.0;
    for (int f = 0; f < nf; ++f) mean_edge += (vtx(m, m.F(f, 0)) - vtx(m, m.F(f, 1))).norm();
    const double cell = 2.0 * mean_edge / nf;
    std::unordered_map<std::int64_t, std::vector<int>> grid;
    std::vector<std::array<int, 6>> range(static_cast<size_t>(nf));
    auto key = [](int i, int j, int k) { return (static_cast<std::int64_t>(i) * 1000003 + j) * 1000003 + k; };
    for (int f = 0; f < nf; ++f) {
        Vector3d mn = vtx(m, m.F(f, 0)), mx = mn;
        for (int k = 1; k < 3; ++k) {
            mn = mn.cwiseMin(vtx(m, m.F(f, k)));
            mx = mx.cwiseMax(vtx(m, m.F(f, k)));
        }
        auto& r = range[static_cast<size_t>(f)];
        for (int a = 0; a < 3; ++a) {
            r[static_cast<size_t>(a)] = static_cast<int>(std::floor((mn[a] - lo[a]) / cell));
            r[static_cast<size_t>(a) + 3] = static_cast<int>(std::floor((mx[a] - lo[a]) / cell));
        }
        for (int i = r[0]; i <= r[3]; ++i)
            for (int j = r[1]; j <= r[4]; ++j)
                for (int k = r[2]; k <= r[5]; ++k) grid[key(i, j, k)].push_back(f);
    }
    long hits = 0;
    std::vector<int> cand;
    for (int f = 0; f < nf; ++f) {
        const auto& r = range[static_cast<size_t>(f)];
        cand.clear();
        for (int i = r[0]; i <= r[3]; ++i)
            for (int j = r[1]; j <= r[4]; ++j)
                for (int k = r[2]; k <= r[5]; ++k) {
                    const auto it = grid.find(key(i, j, k));
                    if (it == grid.end()) continue;
                    for (const int g : it->second)
                        if (g > f) cand.push_back(g);
                }
        std::sort(cand.begin(), cand.end());
        cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
        for (const int g : cand) {
            bool shared = false;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) shared = shared || m.F(f, a) == m.F(g, b);
            if (shared) continue;
            const Vector3d A[3] = {vtx(m, m.F(f, 0)), vtx(m, m.F(f, 1)), vtx(m, m.F(f, 2))};
            const Vector3d B[3] = {vtx(m, m.F(g, 0)), vtx(m, m.F(g, 1)), vtx(m, m.F(g, 2))};
            bool cross = false;
            for (int k = 0; k < 3 && !cross; ++k)
                cross = segment_crosses_triangle(A[k], A[(k + 1) % 3], B[0], B[1], B[2]) ||
                        segment_crosses_triangle(B[k], B[(k + 1) % 3], A[0], A[1], A[2]);
            if (cross) ++hits;
        }
    }
    return hits;
}

// ------------------------------------------------------------------------------------ icosphere

TEST(ProceduralIcosphere, CountsRadiusTopologyAndVolume) {
    const double r = 2.5;
    for (int s = 0; s <= 4; ++s) {
        SCOPED_TRACE("subdivisions " + std::to_string(s));
        const Mesh m = canonform::procedural::make_icosphere(s, r);
        const long p = 1L << (2 * s);  // 4^s
        EXPECT_EQ(m.V.rows(), 10 * p + 2);
        EXPECT_EQ(m.F.rows(), 20 * p);
        for (int i = 0; i < m.V.rows(); ++i) ASSERT_NEAR(m.V.row(i).norm(), r, 1e-12);
        const Topology t = topology(m);
        EXPECT_TRUE(t.oriented_manifold) << t.problem;
        EXPECT_TRUE(t.fans_are_discs) << t.problem;
        EXPECT_TRUE(t.all_vertices_used);
        EXPECT_EQ(t.boundary_edges, 0);
        EXPECT_EQ(t.components, 1);
        EXPECT_EQ(t.euler, 2);
        const double vol = signed_volume(m), sphere = 4.0 / 3.0 * kPi * r * r * r;
        EXPECT_GT(vol, 0.0);  // outward orientation
        if (s >= 3) {
            EXPECT_NEAR(vol / sphere, 1.0, 0.03);
        }
        const auto [min_area, min_angle] = min_area_and_angle(m);
        EXPECT_GT(min_area, 0.0);
        EXPECT_GT(min_angle, 40.0 * kPi / 180.0);
    }
}

TEST(ProceduralIcosphere, RejectsBadArguments) {
    EXPECT_THROW(canonform::procedural::make_icosphere(-1), std::invalid_argument);
    EXPECT_THROW(canonform::procedural::make_icosphere(2, 0.0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------- torus

TEST(ProceduralTorus, ClosedGenusOneWithTheRightVolume) {
    const double R = 1.0, r = 0.3;
    const Mesh m = canonform::procedural::make_torus(64, 32, R, r);
    EXPECT_EQ(m.V.rows(), 64 * 32);
    EXPECT_EQ(m.F.rows(), 2 * 64 * 32);
    const Topology t = topology(m);
    EXPECT_TRUE(t.oriented_manifold) << t.problem;
    EXPECT_TRUE(t.fans_are_discs) << t.problem;
    EXPECT_EQ(t.boundary_edges, 0);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.euler, 0);
    EXPECT_NEAR(signed_volume(m) / (2.0 * kPi * kPi * R * r * r), 1.0, 0.02);
    // Every vertex at distance r from the core circle.
    for (int i = 0; i < m.V.rows(); ++i) {
        const Vector3d p = vtx(m, i);
        const double rho = std::hypot(p.x(), p.y());
        ASSERT_NEAR(std::hypot(rho - R, p.z()), r, 1e-12);
    }
    EXPECT_THROW(canonform::procedural::make_torus(2, 8), std::invalid_argument);
    EXPECT_THROW(canonform::procedural::make_torus(8, 8, 0.2, 0.3), std::invalid_argument);
}

// ----------------------------------------------------------------------------------------- disc

TEST(ProceduralDisc, OneBoundaryLoopFlatAndUpwards) {
    const double radius = 1.7;
    for (const int target : {7, 100, 1000, 5000}) {
        SCOPED_TRACE("target " + std::to_string(target));
        const Mesh m = canonform::procedural::make_disc(target, radius);
        EXPECT_NEAR(static_cast<double>(m.V.rows()), target, 0.15 * target + 1);
        const Topology t = topology(m);
        EXPECT_TRUE(t.oriented_manifold) << t.problem;
        EXPECT_TRUE(t.fans_are_discs) << t.problem;
        EXPECT_TRUE(t.all_vertices_used);
        EXPECT_EQ(t.boundary_loops, 1);
        EXPECT_EQ(t.components, 1);
        EXPECT_EQ(t.euler, 1);
        for (int i = 0; i < m.V.rows(); ++i) {
            ASSERT_EQ(m.V(i, 2), 0.0);
            ASSERT_LE(m.V.row(i).norm(), radius * (1 + 1e-12));
        }
        for (int f = 0; f < m.F.rows(); ++f) {
            const Vector3d n =
                (vtx(m, m.F(f, 1)) - vtx(m, m.F(f, 0))).cross(vtx(m, m.F(f, 2)) - vtx(m, m.F(f, 0)));
            ASSERT_GT(n.z(), 0.0) << "face " << f;
        }
        if (target >= 1000) {
            EXPECT_NEAR(total_area(m) / (kPi * radius * radius), 1.0, 0.01);
        }
        const auto [min_area, min_angle] = min_area_and_angle(m);
        EXPECT_GT(min_area, 0.0);
        EXPECT_GT(min_angle, 20.0 * kPi / 180.0);
    }
    EXPECT_THROW(canonform::procedural::make_disc(3), std::invalid_argument);
}

// --------------------------------------------------------------------------------------- figure

/// Figures are expensive enough to share between tests.
const Figure& figure(int target, int pose) {
    static std::map<std::pair<int, int>, Figure> cache;
    const auto it = cache.find({target, pose});
    if (it != cache.end()) return it->second;
    return cache
        .emplace(std::make_pair(target, pose),
                 canonform::procedural::make_figure(target, canonform::procedural::figure_pose(pose)))
        .first->second;
}

class ProceduralFigureAtTarget : public ::testing::TestWithParam<int> {};

TEST_P(ProceduralFigureAtTarget, VertexCountNearTarget) {
    const int target = GetParam();
    const Figure& f = figure(target, 0);
    EXPECT_NEAR(static_cast<double>(f.mesh.V.rows()), target, 0.25 * target);
}

TEST_P(ProceduralFigureAtTarget, WatertightGenusZeroSingleComponent) {
    for (const int pose : {0, 3}) {
        SCOPED_TRACE("pose " + std::to_string(pose));
        const Figure& f = figure(GetParam(), pose);
        const Topology t = topology(f.mesh);
        EXPECT_TRUE(t.oriented_manifold) << t.problem;
        EXPECT_TRUE(t.fans_are_discs) << t.problem;
        EXPECT_TRUE(t.all_vertices_used);
        EXPECT_EQ(t.boundary_edges, 0);
        EXPECT_EQ(t.components, 1);
        EXPECT_EQ(t.euler, 2);
        EXPECT_GT(signed_volume(f.mesh), 0.0);
    }
}

TEST_P(ProceduralFigureAtTarget, NoDegenerateTriangles) {
    for (const int pose : {0, 3}) {
        SCOPED_TRACE("pose " + std::to_string(pose));
        const auto [min_area, min_angle] = min_area_and_angle(figure(GetParam(), pose).mesh);
        EXPECT_GT(min_area, 0.0);
        EXPECT_GT(min_angle, 1.0 * kPi / 180.0);
    }
}

TEST_P(ProceduralFigureAtTarget, PosesShareConnectivityAndAreNearIsometric) {
    const Figure& rest = figure(GetParam(), 0);
    const Figure& posed = figure(GetParam(), 3);
    ASSERT_EQ(rest.mesh.V.rows(), posed.mesh.V.rows());
    ASSERT_EQ(rest.mesh.F.rows(), posed.mesh.F.rows());
    EXPECT_TRUE(rest.mesh.F == posed.mesh.F);
    std::vector<double> change;
    for (int f = 0; f < rest.mesh.F.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = rest.mesh.F(f, k), b = rest.mesh.F(f, (k + 1) % 3);
            const double l0 = (vtx(rest.mesh, a) - vtx(rest.mesh, b)).norm();
            const double l1 = (vtx(posed.mesh, a) - vtx(posed.mesh, b)).norm();
            change.push_back(std::abs(l1 / l0 - 1.0));
        }
    std::nth_element(change.begin(), change.begin() + static_cast<long>(change.size() / 2), change.end());
    EXPECT_LT(change[change.size() / 2], 0.05);
    // ... and the pose really differs from the rest pose.
    EXPECT_GT((rest.mesh.V - posed.mesh.V).rowwise().norm().maxCoeff(), 0.2);
}

TEST_P(ProceduralFigureAtTarget, LimbTipsOnTheSurfaceAndFarApart) {
    const std::vector<std::string> names = {"head",      "left_hand",  "right_hand",
                                            "left_foot", "right_foot", "tail"};
    const Figure& rest = figure(GetParam(), 0);
    const double height = rest.mesh.V.col(2).maxCoeff() - rest.mesh.V.col(2).minCoeff();
    EXPECT_GT(height, 1.8);
    EXPECT_LT(height, 2.2);
    for (const int pose : {0, 3}) {
        SCOPED_TRACE("pose " + std::to_string(pose));
        const Figure& f = figure(GetParam(), pose);
        ASSERT_EQ(f.limb_names, names);
        ASSERT_EQ(f.limb_tips.size(), names.size());
        ASSERT_EQ(f.limb_radius.size(), names.size());
        ASSERT_EQ(f.limb_tip_vertex.size(), names.size());
        for (size_t i = 0; i < names.size(); ++i) {
            SCOPED_TRACE(names[i]);
            const double nearest =
                (f.mesh.V.rowwise() - f.limb_tips[i].transpose()).rowwise().norm().minCoeff();
            EXPECT_LT(nearest, 1.5 * f.limb_radius[i]);
            EXPECT_GT(f.limb_radius[i], 0.0);
            const int v = f.limb_tip_vertex[i];
            ASSERT_GE(v, 0);
            ASSERT_LT(v, f.mesh.V.rows());
            EXPECT_LT((vtx(f.mesh, v) - f.limb_tips[i]).norm(), 1.5 * f.limb_radius[i]);
            for (size_t j = i + 1; j < names.size(); ++j)
                EXPECT_GT((f.limb_tips[i] - f.limb_tips[j]).norm(), 0.3 * height)
                    << names[i] << " - " << names[j];
        }
    }
    // The tips are the extremes of the rest pose: head highest, hands farthest left/right, ...
    const auto& V = rest.mesh.V;
    Eigen::Index top, left, right;
    V.col(2).maxCoeff(&top);
    V.col(0).maxCoeff(&left);
    V.col(0).minCoeff(&right);
    EXPECT_LT((vtx(rest.mesh, static_cast<int>(top)) - rest.limb_tips[0]).norm(), 0.1);
    EXPECT_LT((vtx(rest.mesh, static_cast<int>(left)) - rest.limb_tips[1]).norm(), 0.1);
    EXPECT_LT((vtx(rest.mesh, static_cast<int>(right)) - rest.limb_tips[2]).norm(), 0.1);
}

INSTANTIATE_TEST_SUITE_P(Targets, ProceduralFigureAtTarget, ::testing::Values(2000, 10000));

TEST(ProceduralFigure, NamedPosesDoNotSelfIntersect) {
    for (int pose = 0; pose < canonform::procedural::kFigureNamedPoses; ++pose) {
        SCOPED_TRACE("pose " + std::to_string(pose));
        const Figure& f = figure(4000, pose);
        EXPECT_EQ(self_intersections(f.mesh), 0);
        EXPECT_GT(min_area_and_angle(f.mesh).second, 1.0 * kPi / 180.0);
    }
}

TEST(ProceduralFigure, RandomPosesAreDeterministicAndClean) {
    for (const int id : {6, 7, 23, 1000}) {
        SCOPED_TRACE("pose " + std::to_string(id));
        const FigurePose a = canonform::procedural::figure_pose(id),
                         b = canonform::procedural::figure_pose(id);
        EXPECT_EQ(a.left_arm.elbow_bend, b.left_arm.elbow_bend);
        EXPECT_EQ(a.right_leg.knee_bend, b.right_leg.knee_bend);
        EXPECT_EQ(a.tail_curl, b.tail_curl);
        EXPECT_NE(a.left_arm.shoulder_down,
                  canonform::procedural::figure_pose(id + 1).left_arm.shoulder_down);
        const Figure f = canonform::procedural::make_figure(2000, a);
        EXPECT_EQ(self_intersections(f.mesh), 0);
        EXPECT_GT(min_area_and_angle(f.mesh).second, 1.0 * kPi / 180.0);
    }
}

TEST(ProceduralFigure, NamedPosesAreDistinct) {
    for (int i = 0; i < canonform::procedural::kFigureNamedPoses; ++i)
        for (int j = i + 1; j < canonform::procedural::kFigureNamedPoses; ++j) {
            const Figure& a = figure(2000, i);
            const Figure& b = figure(2000, j);
            EXPECT_GT((a.mesh.V - b.mesh.V).rowwise().norm().maxCoeff(), 0.1) << i << " vs " << j;
        }
}

TEST(ProceduralFigure, ValidAndRepeatableAtOtherTargets) {
    for (const int target : {500, 1234, 30000}) {
        SCOPED_TRACE("target " + std::to_string(target));
        const Figure a = canonform::procedural::make_figure(target, canonform::procedural::figure_pose(2));
        EXPECT_NEAR(static_cast<double>(a.mesh.V.rows()), target, 0.25 * target);
        const Topology t = topology(a.mesh);
        EXPECT_TRUE(t.oriented_manifold && t.fans_are_discs) << t.problem;
        EXPECT_EQ(t.components, 1);
        EXPECT_EQ(t.euler, 2);
        const Figure b = canonform::procedural::make_figure(target, canonform::procedural::figure_pose(2));
        EXPECT_TRUE(a.mesh.V == b.mesh.V);
        EXPECT_TRUE(a.mesh.F == b.mesh.F);
    }
}

TEST(ProceduralFigureClasses, StandardProportionsGiveExactlyTheStandardFigure) {
    const Figure a = canonform::procedural::make_figure(2000, canonform::procedural::figure_pose(3));
    const Figure b = canonform::procedural::make_figure(2000, canonform::procedural::figure_pose(3),
                                                        canonform::procedural::figure_class("standard"));
    EXPECT_TRUE(a.mesh.V == b.mesh.V);
    EXPECT_TRUE(a.mesh.F == b.mesh.F);
}

TEST(ProceduralFigureClasses, EveryClassIsCleanInEveryNamedPoseWithTheSameFaces) {
    const Figure standard = canonform::procedural::make_figure(2000, FigurePose{});
    for (const std::string& name : canonform::procedural::figure_class_names()) {
        for (int pose = 0; pose < canonform::procedural::kFigureNamedPoses; ++pose) {
            SCOPED_TRACE(name + ", pose " + std::to_string(pose));
            const Figure f = canonform::procedural::make_figure(
                2000, canonform::procedural::figure_pose(pose), canonform::procedural::figure_class(name));
            EXPECT_TRUE(f.mesh.F == standard.mesh.F);
            const Topology t = topology(f.mesh);
            EXPECT_TRUE(t.oriented_manifold && t.fans_are_discs) << t.problem;
            EXPECT_EQ(t.euler, 2);
            EXPECT_EQ(self_intersections(f.mesh), 0);
            EXPECT_GT(min_area_and_angle(f.mesh).second, 1.0 * kPi / 180.0);
            if (name != "standard") {
                EXPECT_GT((f.mesh.V - standard.mesh.V).rowwise().norm().maxCoeff(), 0.05);
            }
        }
    }
    EXPECT_EQ(static_cast<int>(canonform::procedural::figure_class_names().size()),
              canonform::procedural::kFigureClasses);
}

TEST(ProceduralFigureClasses, RandomPosesOfTheGeneratedCollectionAreClean) {
    // `canonform generate --collection` (seed 0) poses class c's figure k >= 6 with pose id
    // 1000 + 37 c + k; ten poses per class by default.
    const auto names = canonform::procedural::figure_class_names();
    for (size_t c = 0; c < names.size(); ++c)
        for (int k = canonform::procedural::kFigureNamedPoses; k < 10; ++k) {
            const int id = 1000 + 37 * static_cast<int>(c) + k;
            SCOPED_TRACE(names[c] + ", pose " + std::to_string(id));
            const Figure f = canonform::procedural::make_figure(
                2000, canonform::procedural::figure_pose(id), canonform::procedural::figure_class(names[c]));
            EXPECT_EQ(self_intersections(f.mesh), 0);
            EXPECT_GT(min_area_and_angle(f.mesh).second, 1.0 * kPi / 180.0);
        }
}

TEST(ProceduralFigureClasses, LengthFactorsStretchTheLimbsByThatFactor) {
    // Rest pose: the left hand tip lies at the shoulder joint (x = 0.26) plus the arm's length
    // along x; the tail tip behind the tail's base (y = 0.10) by the tail's length along its axis.
    const Figure s = canonform::procedural::make_figure(3000, FigurePose{});
    canonform::procedural::FigureProportions p;
    p.arm_length = 1.5;
    p.tail_length = 0.6;
    const Figure l = canonform::procedural::make_figure(3000, FigurePose{}, p);
    const double arm_s = s.limb_tips[1].x() - 0.26, arm_l = l.limb_tips[1].x() - 0.26;
    EXPECT_NEAR(arm_l / arm_s, 1.5, 0.03);
    const double tail_s = (s.limb_tips[5] - Vector3d(0, 0.10, 0.86)).norm();
    const double tail_l = (l.limb_tips[5] - Vector3d(0, 0.10, 0.86)).norm();
    EXPECT_NEAR(tail_l / tail_s, 0.6, 0.03);
    // The legs did not change.
    EXPECT_NEAR((l.limb_tips[3] - s.limb_tips[3]).norm(), 0.0, 1e-9);
}

TEST(ProceduralFigureClasses, RejectsUnknownClassesAndProportionsOutOfRange) {
    EXPECT_THROW(canonform::procedural::figure_class("giraffe"), std::invalid_argument);
    canonform::procedural::FigureProportions p;
    p.leg_length = 3.0;
    EXPECT_THROW(canonform::procedural::make_figure(2000, FigurePose{}, p), std::invalid_argument);
    p.leg_length = 0.0;
    EXPECT_THROW(canonform::procedural::make_figure(2000, FigurePose{}, p), std::invalid_argument);
}

TEST(ProceduralFigure, RejectsBadArguments) {
    EXPECT_THROW(canonform::procedural::figure_pose(-1), std::invalid_argument);
    EXPECT_THROW(canonform::procedural::make_figure(10, FigurePose{}), std::invalid_argument);
}

}  // namespace
