// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/geodesic_distances.h"
#include "canonform/surface/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <queue>
#include <random>
#include <vector>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::procedural;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Plain Dijkstra on the edge graph (overestimates geodesics).
Eigen::VectorXd edge_dijkstra(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int source) {
    const int n = static_cast<int>(V.rows());
    const VertexAdjacency adj = vertex_adjacency(n, unique_edges(F));
    Eigen::VectorXd d = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
    d[source] = 0;
    q.emplace(0.0, source);
    while (!q.empty()) {
        const auto [du, u] = q.top();
        q.pop();
        if (du > d[u]) continue;
        for (int k = adj.offsets[u]; k < adj.offsets[u + 1]; ++k) {
            const int w = adj.neighbors[k];
            const double t = du + (V.row(u) - V.row(w)).norm();
            if (t < d[w]) {
                d[w] = t;
                q.emplace(t, w);
            }
        }
    }
    return d;
}

/// Mean of |d - exact| / exact over vertices other than the source and its one-ring.
double mean_relative_error(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int source,
                           const Eigen::VectorXd& d, const std::function<double(int)>& exact) {
    const VertexAdjacency adj = vertex_adjacency(static_cast<int>(V.rows()), unique_edges(F));
    std::vector<bool> skip(V.rows(), false);
    skip[source] = true;
    for (int k = adj.offsets[source]; k < adj.offsets[source + 1]; ++k) skip[adj.neighbors[k]] = true;
    double sum = 0;
    int count = 0;
    for (int v = 0; v < V.rows(); ++v) {
        if (skip[v]) continue;
        const double e = exact(v);
        sum += std::abs(d[v] - e) / e;
        ++count;
    }
    return sum / count;
}

/// Vertex of V nearest to p.
int nearest_vertex(const Eigen::MatrixXd& V, const Eigen::RowVector3d& p) {
    Eigen::Index best;
    (V.rowwise() - p).rowwise().squaredNorm().minCoeff(&best);
    return static_cast<int>(best);
}

/// Flat triangular lattice stretched along x by `stretch` (stretch 3 gives 120-degree angles).
Mesh stretched_lattice(int nx, int ny, double stretch) {
    Mesh m;
    m.V.resize(nx * ny, 3);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            m.V.row(j * nx + i) << stretch * (i + 0.5 * (j % 2)), 0.8660254037844386 * j, 0.0;
    std::vector<Eigen::Vector3i> f;
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            const int a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
            if (j % 2 == 0) {
                f.emplace_back(a, b, c);
                f.emplace_back(b, d, c);
            } else {
                f.emplace_back(a, d, c);
                f.emplace_back(a, b, d);
            }
        }
    m.F.resize(static_cast<int>(f.size()), 3);
    for (size_t k = 0; k < f.size(); ++k) m.F.row(static_cast<int>(k)) = f[k].transpose();
    return m;
}

double sphere_error(const Mesh& s, double r, int source, const Eigen::VectorXd& d) {
    const Eigen::RowVector3d p = s.V.row(source);
    return mean_relative_error(s.V, s.F, source, d, [&](int v) {
        const double c = std::clamp(p.dot(s.V.row(v)) / (r * r), -1.0, 1.0);
        return r * std::acos(c);
    });
}

double plane_error(const Mesh& m, int source, const Eigen::VectorXd& d) {
    const Eigen::RowVector3d p = m.V.row(source);
    return mean_relative_error(m.V, m.F, source, d, [&](int v) { return (m.V.row(v) - p).norm(); });
}

}  // namespace

TEST(GeodesicDistances, GreatCircleDistancesOnASphere) {
    const double r = 2.0;
    const Mesh s = make_icosphere(5, r);  // 10242 vertices, edge about 0.07
    const FastMarching fm(s.V, s.F);
    EXPECT_EQ(fm.stats().obtuse_corners, 0);
    for (int source : {0, 1234, 7777}) {
        const Eigen::VectorXd d = fm.distances_from(source);
        ASSERT_EQ(d.size(), s.V.rows());
        EXPECT_EQ(d[source], 0.0);
        EXPECT_TRUE(d.allFinite());
        const double err = sphere_error(s, r, source, d);
        std::printf("sphere (%ld vertices), source %d: mean relative error %.4f%%\n",
                    static_cast<long>(s.V.rows()), source, 100 * err);
        EXPECT_LT(err, 0.02);
        // The antipode is at pi r.
        EXPECT_NEAR(d.maxCoeff(), kPi * r, 0.02 * kPi * r);
    }
}

TEST(GeodesicDistances, EuclideanDistancesOnAFlatDisc) {
    const Mesh disc = make_disc(5000);
    const int centre = 0;
    const int off = nearest_vertex(disc.V, Eigen::RowVector3d(0.4, 0.25, 0.0));
    const FastMarching fm(disc.V, disc.F);
    for (int source : {centre, off}) {
        const Eigen::VectorXd d = fm.distances_from(source);
        const double err = plane_error(disc, source, d);
        std::printf("disc (%ld vertices), source %d: mean relative error %.4f%%\n",
                    static_cast<long>(disc.V.rows()), source, 100 * err);
        EXPECT_LT(err, 0.02);
    }
    // The free function agrees with the class.
    EXPECT_EQ((geodesic_distances_from(disc.V, disc.F, off) - fm.distances_from(off)).norm(), 0.0);
}

TEST(GeodesicDistances, MoreAccurateThanEdgeDijkstra) {
    const Mesh disc = make_disc(5000);
    const FastMarching fm(disc.V, disc.F);
    for (const Eigen::RowVector3d& p :
         {Eigen::RowVector3d(0, 0, 0), Eigen::RowVector3d(0.4, 0.25, 0), Eigen::RowVector3d(-0.7, 0.1, 0)}) {
        const int source = nearest_vertex(disc.V, p);
        const double fmm = plane_error(disc, source, fm.distances_from(source));
        const Eigen::VectorXd dij = edge_dijkstra(disc.V, disc.F, source);
        const double dijkstra = plane_error(disc, source, dij);
        std::printf("disc source %d: fast marching %.4f%%, edge Dijkstra %.4f%%\n", source, 100 * fmm,
                    100 * dijkstra);
        EXPECT_LT(fmm, 0.5 * dijkstra);
        // Fast marching is never longer than the edge paths it improves on (up to rounding).
        EXPECT_LE((fm.distances_from(source) - dij).maxCoeff(), 1e-12);
    }
}

TEST(GeodesicDistances, UnfoldingHandlesObtuseTriangles) {
    // All triangles have a 120-degree corner.
    const Mesh m = stretched_lattice(40, 100, 3.0);
    const FastMarching unfolded(m.V, m.F, true), plain(m.V, m.F, false);
    EXPECT_GT(unfolded.stats().obtuse_corners, 0);
    EXPECT_EQ(unfolded.stats().obtuse_corners, plain.stats().obtuse_corners);
    EXPECT_GT(unfolded.stats().unfolded_corners, unfolded.stats().obtuse_corners / 2);
    EXPECT_EQ(plain.stats().unfolded_corners, 0);
    const int source = nearest_vertex(m.V, Eigen::RowVector3d(60.0, 43.0, 0.0));
    const double e_unfold = plane_error(m, source, unfolded.distances_from(source));
    const double e_plain = plane_error(m, source, plain.distances_from(source));
    const double e_dijkstra = plane_error(m, source, edge_dijkstra(m.V, m.F, source));
    std::printf(
        "obtuse lattice: unfolded %.4f%%, without unfolding %.4f%%, edge Dijkstra %.4f%% "
        "(%d of %d obtuse corners split)\n",
        100 * e_unfold, 100 * e_plain, 100 * e_dijkstra, unfolded.stats().unfolded_corners,
        unfolded.stats().obtuse_corners);
    EXPECT_LT(e_unfold, 0.02);
    EXPECT_LT(e_unfold, 0.5 * e_plain);
}

TEST(GeodesicDistances, AllPairsIsAMetricAndIndependentOfThreads) {
    const Mesh s = make_icosphere(3, 1.5);  // 642 vertices
    const int n = static_cast<int>(s.V.rows());
    GeodesicOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const Eigen::MatrixXd D1 = all_pairs_geodesic_distances(s.V, s.F, one);
    const Eigen::MatrixXd D2 = all_pairs_geodesic_distances(s.V, s.F, two);
    ASSERT_EQ(D1.rows(), n);
    ASSERT_EQ(D1.cols(), n);
    EXPECT_TRUE(D1.allFinite());
    EXPECT_LE((D1 - D2).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ((D1 - D1.transpose()).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(D1.diagonal().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GE(D1.minCoeff(), 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (i != j) {
                ASSERT_GT(D1(i, j), 0.0);
            }

    // The average of the two fast marches.
    const FastMarching fm(s.V, s.F);
    const Eigen::VectorXd d7 = fm.distances_from(7), d300 = fm.distances_from(300);
    EXPECT_NEAR(D1(7, 300), 0.5 * (d7[300] + d300[7]), 1e-14);

    // Triangle inequality on random triples, up to the first-order discretisation error.
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> pick(0, n - 1);
    const double h = (s.V.row(s.F(0, 0)) - s.V.row(s.F(0, 1))).norm();
    double worst = -1e300;
    for (int t = 0; t < 20000; ++t) {
        const int i = pick(rng), j = pick(rng), k = pick(rng);
        worst = std::max(worst, D1(i, k) - D1(i, j) - D1(j, k));
    }
    std::printf("all pairs (%d vertices): worst triangle-inequality violation %.2e (edge %.3f)\n", n, worst,
                h);
    EXPECT_LE(worst, 0.05 * h);

    // Close to the great-circle distances.
    Eigen::MatrixXd G = (s.V * s.V.transpose() / (1.5 * 1.5)).cwiseMax(-1.0).cwiseMin(1.0);
    G = G.array().acos() * 1.5;
    EXPECT_LT((D1 - G).cwiseAbs().maxCoeff(), 0.05 * 1.5 * kPi);
}

TEST(GeodesicDistances, ProgressAndCancellation) {
    const Mesh s = make_icosphere(3);
    std::vector<double> seen;
    GeodesicOptions o;
    o.threads = 2;
    o.progress = [&](double f, const char* stage) {
        EXPECT_STREQ(stage, "geodesic distances");
        seen.push_back(f);
        return true;
    };
    all_pairs_geodesic_distances(s.V, s.F, o);
    ASSERT_GE(seen.size(), 20u);
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));

    int calls = 0;
    o.progress = [&](double, const char*) { return ++calls < 5; };
    EXPECT_THROW(all_pairs_geodesic_distances(s.V, s.F, o), Cancelled);
    EXPECT_EQ(calls, 5);
}

TEST(GeodesicDistances, RejectsBadInputAndHandlesComponents) {
    const Mesh s = make_icosphere(1);
    EXPECT_THROW(geodesic_distances_from(s.V, s.F, -1), InputError);
    EXPECT_THROW(geodesic_distances_from(s.V, s.F, static_cast<int>(s.V.rows())), InputError);
    Eigen::MatrixXi F = s.F;
    F(3, 1) = 1000;
    EXPECT_THROW(FastMarching(s.V, F), InputError);
    Eigen::MatrixXd V = s.V;
    V(2, 2) = std::nan("");
    EXPECT_THROW(FastMarching(V, s.F), InputError);
    EXPECT_THROW(FastMarching(s.V.leftCols(2), s.F), InputError);

    // Two spheres: distances across components are infinite.
    const int n = static_cast<int>(s.V.rows());
    Eigen::MatrixXd V2(2 * n, 3);
    V2 << s.V, s.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
    Eigen::MatrixXi F2(2 * s.F.rows(), 3);
    F2 << s.F, s.F.array() + n;
    const Eigen::VectorXd d = geodesic_distances_from(V2, F2, 0);
    EXPECT_TRUE(d.head(n).allFinite());
    EXPECT_TRUE(std::isinf(d[n]));
    EXPECT_TRUE(d.tail(n).array().isInf().all());
}

TEST(GeodesicDistances, CostEstimates) {
    EXPECT_GE(all_pairs_geodesic_bytes(1000), 8u * 1000 * 1000);
    EXPECT_LT(all_pairs_geodesic_bytes(1000), 2 * 8u * 1000 * 1000);
    EXPECT_GT(all_pairs_geodesic_bytes(20000), all_pairs_geodesic_bytes(10000));
    EXPECT_GT(all_pairs_geodesic_seconds_estimate(4000), 3.5 * all_pairs_geodesic_seconds_estimate(2000));
    EXPECT_GT(all_pairs_geodesic_seconds_estimate(2000), 0.0);
}

TEST(GeodesicDistances, PrintAllPairsTimings) {
    // Printed, not asserted (timings depend on the machine).
    const Figure f = make_figure(2000, figure_pose(0));
    for (int threads : {1, 2}) {
        GeodesicOptions o;
        o.threads = threads;
        const auto t0 = std::chrono::steady_clock::now();
        const Eigen::MatrixXd D = all_pairs_geodesic_distances(f.mesh.V, f.mesh.F, o);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("all pairs, figure with %ld vertices, %d thread(s): %.3f s (1-core estimate %.3f s)\n",
                    static_cast<long>(D.rows()), threads, sec, all_pairs_geodesic_seconds_estimate(D.rows()));
        EXPECT_TRUE(D.allFinite());
    }
}
