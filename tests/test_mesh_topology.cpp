// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/errors.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::procedural;

namespace {

/// The InputError message of validate_mesh, or "" if it passes.
std::string problem(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    try {
        validate_mesh(V, F);
        return "";
    } catch (const InputError& e) {
        return e.what();
    }
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

}  // namespace

TEST(MeshTopology, EdgesAdjacencyAndComponents) {
    Eigen::MatrixXi F(2, 3);
    F << 0, 1, 2, 2, 1, 3;
    const Eigen::MatrixXi E = unique_edges(F);
    ASSERT_EQ(E.rows(), 5);
    const VertexAdjacency adj = vertex_adjacency(4, E);
    EXPECT_EQ(
        std::vector<int>(adj.neighbors.begin() + adj.offsets[1], adj.neighbors.begin() + adj.offsets[2]),
        (std::vector<int>{0, 2, 3}));
    const auto bnd = boundary_vertices(4, F);
    EXPECT_TRUE(bnd[0] && bnd[1] && bnd[2] && bnd[3]);
    int count = 0;
    Eigen::MatrixXi E2(2, 2);
    E2 << 0, 1, 2, 3;
    const auto label = connected_components(5, E2, &count);
    EXPECT_EQ(count, 3);
    EXPECT_EQ(label, (std::vector<int>{0, 0, 1, 1, 2}));
}

TEST(MeshTopology, ValidMeshesPassAndAreReported) {
    const Mesh s = make_icosphere(2);
    const MeshReport r = validate_mesh(s.V, s.F);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.components, 1);
    EXPECT_EQ(r.boundary_edges, 0);
    const Mesh d = make_disc(300);
    EXPECT_EQ(problem(d.V, d.F), "") << "boundaries are allowed";
    EXPECT_EQ(validate_mesh(d.V, d.F).euler_characteristic, 1);
}

TEST(MeshTopology, EveryKindOfBadInputIsNamed) {
    const Mesh s = make_icosphere(1);  // 42 vertices
    EXPECT_TRUE(contains(problem(Eigen::MatrixXd(0, 3), Eigen::MatrixXi(0, 3)), "no vertices"));
    EXPECT_TRUE(contains(problem(s.V, Eigen::MatrixXi(0, 3)), "point cloud"));

    Eigen::MatrixXd V = s.V;
    V(7, 0) = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(contains(problem(V, s.F), "NaN or infinite"));

    const Mesh tiny = make_icosphere(0);  // 12 vertices
    ValidationOptions strict;
    strict.min_vertices = 20;
    try {
        validate_mesh(tiny.V, tiny.F, strict);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_TRUE(contains(e.what(), "only 12 vertices"));
    }
    Eigen::MatrixXi F = s.F;
    F(0, 2) = F(0, 1);  // repeated vertex
    EXPECT_TRUE(contains(problem(s.V, F), "degenerate"));
    V = s.V;
    V.row(s.F(0, 2)) = 0.5 * (V.row(s.F(0, 0)) + V.row(s.F(0, 1)));  // zero area
    EXPECT_TRUE(contains(problem(V, s.F), "degenerate"));

    // A third face on an existing edge: non-manifold.
    Eigen::MatrixXd V3(s.V.rows() + 1, 3);
    V3 << s.V, Eigen::RowVector3d(3, 3, 3);
    Eigen::MatrixXi F3(s.F.rows() + 1, 3);
    F3 << s.F, Eigen::RowVector3i(s.F(0, 0), s.F(0, 1), static_cast<int>(s.V.rows()));
    EXPECT_TRUE(contains(problem(V3, F3), "non-manifold"));

    // Two spheres: two components.
    Eigen::MatrixXd V2(2 * s.V.rows(), 3);
    V2 << s.V, (s.V.array() + 5.0).matrix();
    Eigen::MatrixXi F2(2 * s.F.rows(), 3);
    F2 << s.F, (s.F.array() + static_cast<int>(s.V.rows())).matrix();
    EXPECT_TRUE(contains(problem(V2, F2), "2 connected components"));

    // An extra vertex no face uses.
    Eigen::MatrixXd V4(s.V.rows() + 1, 3);
    V4 << s.V, Eigen::RowVector3d(0, 0, 0);
    EXPECT_TRUE(contains(problem(V4, s.F), "belong to no face"));

    F = s.F;
    F(2, 1) = 1000;
    EXPECT_TRUE(contains(problem(s.V, F), "out of range"));
}

TEST(MeshTopology, TinyAndHugeCoordinatesAreNotDegenerateFaces) {
    // Issue 11: a mesh with coordinates of 1e200 or 1e-200 was refused for "5996 degenerate faces"
    // (the area test squared the bounding-box diagonal: inf or 0).
    const Mesh s = make_icosphere(2);
    for (double scale : {1e200, 1e-200, 1e-300, 1e250}) {
        const MeshReport r = validate_mesh(s.V * scale, s.F);
        EXPECT_EQ(r.faces, s.F.rows()) << scale;
    }
    EXPECT_TRUE(
        contains(problem(s.V * 1e300, s.F), "coordinates reach"));  // beyond what sums and squares hold
    EXPECT_TRUE(contains(problem(Eigen::MatrixXd::Zero(s.V.rows(), 3), s.F), "are at one point"));
    Eigen::MatrixXd V = s.V * 1e-200;  // a real zero-area face among tiny ones is still one
    V.row(s.F(0, 2)) = 0.5 * (V.row(s.F(0, 0)) + V.row(s.F(0, 1)));
    EXPECT_TRUE(contains(problem(V, s.F), "1 degenerate faces"));
}

TEST(MeshTopology, FaceIndicesAreCheckedBeforeAnyUseAndNamed) {
    const Mesh s = make_icosphere(1);
    for (int bad : {-1, static_cast<int>(s.V.rows()), 100000000}) {
        Eigen::MatrixXi F = s.F;
        F(5, 1) = bad;
        const std::string m = problem(s.V, F);
        EXPECT_TRUE(contains(m, "out of range: face 5 is")) << m;
        EXPECT_TRUE(contains(m, std::to_string(bad))) << m;
    }
}

TEST(MeshTopology, EdgesAndBoundaryMatchASortedReference) {
    // unique_edges() and boundary_vertices() sort half-edges by buckets (linear time); the
    // reference sorts them all with std::sort, as they did before.
    const Mesh d = make_disc(700);
    // A fan: vertex 0 joined to 40 rim vertices, so its bucket of half-edges is larger than the
    // insertion sort takes (the stable_sort fallback), rim faces listed in shuffled order.
    Mesh fan;
    const int rim = 40;
    fan.V.resize(rim + 1, 3);
    fan.V.row(0) << 0, 0, 0.3;
    for (int k = 0; k < rim; ++k)
        fan.V.row(k + 1) << std::cos(2 * M_PI * k / rim), std::sin(2 * M_PI * k / rim), 0;
    fan.F.resize(rim - 1, 3);  // open: one gap in the rim
    for (int k = 0; k + 1 < rim; ++k) {
        const int j = (k * 17) % (rim - 1);
        fan.F.row(k) << 0, j + 1, j + 2;
    }
    for (const Mesh* m : {&d, static_cast<const Mesh*>(&fan)}) {
        const Eigen::MatrixXi& F = m->F;
        std::vector<std::pair<int, int>> half;
        for (int f = 0; f < F.rows(); ++f)
            for (int c = 0; c < 3; ++c)
                half.emplace_back(std::min(F(f, c), F(f, (c + 1) % 3)), std::max(F(f, c), F(f, (c + 1) % 3)));
        std::sort(half.begin(), half.end());
        std::vector<std::pair<int, int>> uniq = half;
        uniq.erase(std::unique(uniq.begin(), uniq.end()), uniq.end());
        const Eigen::MatrixXi E = unique_edges(F);
        ASSERT_EQ(static_cast<size_t>(E.rows()), uniq.size());
        for (Eigen::Index e = 0; e < E.rows(); ++e) {
            EXPECT_EQ(E(e, 0), uniq[static_cast<size_t>(e)].first);
            EXPECT_EQ(E(e, 1), uniq[static_cast<size_t>(e)].second);
        }
        std::vector<bool> ref(static_cast<size_t>(m->V.rows()), false);
        size_t on = 0;
        for (size_t k = 0; k < half.size();) {
            size_t j = k;
            while (j < half.size() && half[j] == half[k]) ++j;
            if (j - k == 1)
                ref[static_cast<size_t>(half[k].first)] = ref[static_cast<size_t>(half[k].second)] = true;
            k = j;
        }
        const std::vector<bool> bnd = boundary_vertices(static_cast<int>(m->V.rows()), F);
        EXPECT_EQ(bnd, ref);
        for (bool b : bnd)
            if (b) ++on;
        EXPECT_GT(on, 0u);  // the disc has a boundary
        // validate_mesh derives both from one sort of the half-edges: the same results.
        const MeshReport report = validate_mesh(m->V, F);
        EXPECT_TRUE(report.edge_list == E);
        EXPECT_EQ(report.boundary, ref);
    }
}
