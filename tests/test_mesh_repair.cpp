// SPDX-License-Identifier: GPL-3.0-or-later
// surface/mesh_repair.h: each step on a mesh built to need it, and the case - a mesh with
// 5 zero-area faces that every method refused - let through with a log of what was removed.
#include "canonform/canonical/method_registry.h"
#include "canonform/common/errors.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"

#include "test_util.h"

#include <gtest/gtest.h>

using namespace canonform;
using namespace canonform::surface;
using namespace canonform::canonical;
using namespace canonform::procedural;

namespace {

/// `m` with `k` zero-area faces added: each splits an edge (a, b) of an existing face (a, b, c)
/// at its midpoint M into (a, M, c), (M, b, c) and adds the sliver (a, b, M) of zero area, as
/// meshes exported from CAD tools have. The result keeps every edge shared by two faces.
Mesh with_zero_area_faces(const Mesh& m, int k) {
    Mesh out = m;
    std::vector<Eigen::RowVector3i> faces;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) faces.push_back(m.F.row(f));
    std::vector<Eigen::RowVector3d> extra;
    for (int s = 0; s < k; ++s) {
        const size_t f = static_cast<size_t>(s) * static_cast<size_t>(m.F.rows()) / 5 + 1;  // faces far apart
        const int a = faces[f](0), b = faces[f](1), c = faces[f](2);
        const int mid = static_cast<int>(m.V.rows() + static_cast<Eigen::Index>(extra.size()));
        extra.push_back(0.5 * (m.V.row(a) + m.V.row(b)));
        faces[f] = Eigen::RowVector3i(a, mid, c);
        faces.push_back(Eigen::RowVector3i(mid, b, c));
        // The neighbour across (a, b) still uses the edge (b, a): the sliver (a, b, mid) closes
        // the T-junction with zero area.
        faces.push_back(Eigen::RowVector3i(b, a, mid));
    }
    out.V.conservativeResize(m.V.rows() + static_cast<Eigen::Index>(extra.size()), 3);
    for (size_t e = 0; e < extra.size(); ++e) out.V.row(m.V.rows() + static_cast<Eigen::Index>(e)) = extra[e];
    out.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (size_t f = 0; f < faces.size(); ++f) out.F.row(static_cast<Eigen::Index>(f)) = faces[f];
    return out;
}

}  // namespace

TEST(MeshRepair, FiveZeroAreaFacesAreRemovedAndEveryMethodRuns) {
    // Issue 11: one mesh of a public 400-model benchmark has 5 zero-area faces and was refused by
    // every method, even `none`.
    const Mesh base = make_figure(1500, figure_pose(1), figure_class("standard")).mesh;
    const Mesh m = with_zero_area_faces(base, 5);
    const std::string refused = test::message_of([&] { validate_mesh(m.V, m.F); });
    EXPECT_NE(refused.find("5 degenerate faces"), std::string::npos) << refused;
    const MeshRepair r = repair_mesh(m.V, m.F);
    EXPECT_EQ(r.degenerate_faces, 5);
    EXPECT_EQ(r.merged_vertices + r.duplicate_faces + r.removed_components + r.unreferenced_vertices, 0);
    EXPECT_EQ(r.mesh.F.rows(), m.F.rows() - 5);
    EXPECT_EQ(r.mesh.V.rows(), m.V.rows());
    EXPECT_EQ(r.summary(),
              "repair: 5 zero-area or repeated-vertex faces removed: " + std::to_string(m.V.rows()) + " -> " +
                  std::to_string(m.V.rows()) + " vertices, " + std::to_string(m.F.rows()) + " -> " +
                  std::to_string(m.F.rows() - 5) + " faces");
    const MeshReport report = validate_mesh(r.mesh.V, r.mesh.F);  // accepted now
    EXPECT_EQ(report.boundary_edges, 15);  // each sliver leaves a crack of zero width (3 boundary edges)
    for (const char* method : {"none", "euclidean-N"}) {
        const MethodSpec spec = parse_method_spec(method);
        const CanonicalForm f = spec.method().run(r.mesh.V, r.mesh.F, spec.settings(), {});
        EXPECT_EQ(f.V.rows(), r.mesh.V.rows());
        EXPECT_TRUE(f.V.allFinite());
    }
}

TEST(MeshRepair, EachStepOnAMeshThatNeedsIt) {
    const Mesh s = make_icosphere(1);  // 42 vertices, 80 faces
    Mesh m = s;
    const Eigen::Index n = m.V.rows();
    // A duplicate of vertex 0 used by face 0 instead of vertex 0 (a crack that merging closes).
    m.V.conservativeResize(n + 3, 3);
    m.V.row(n) = m.V.row(0);
    for (int c = 0; c < 3; ++c)
        if (m.F(0, c) == 0) m.F(0, c) = static_cast<int>(n);
    // An unreferenced vertex, and a separate small triangle (a second component).
    m.V.row(n + 1) << 5, 5, 5;
    m.V.row(n + 2) << 6, 5, 5;
    m.V.conservativeResize(n + 4, 3);
    m.V.row(n + 3) << 5, 6, 5;
    m.F.conservativeResize(s.F.rows() + 3, 3);
    m.F.row(s.F.rows()) = s.F.row(1).reverse();  // a duplicate face (the other orientation)
    m.F.row(s.F.rows() + 1) << static_cast<int>(n + 1), static_cast<int>(n + 2), static_cast<int>(n + 3);
    m.F.row(s.F.rows() + 2) << 3, 3, 4;  // a repeated vertex
    EXPECT_THROW(validate_mesh(m.V, m.F), InputError);
    const MeshRepair r = repair_mesh(m.V, m.F);
    EXPECT_EQ(r.merged_vertices, 1);
    EXPECT_EQ(r.degenerate_faces, 1);
    EXPECT_EQ(r.duplicate_faces, 1);
    EXPECT_EQ(r.removed_components, 1);
    EXPECT_EQ(r.component_faces, 1);
    EXPECT_EQ(r.unreferenced_vertices, 3);  // the triangle's three, once their face is gone
    EXPECT_EQ(r.mesh.V.rows(), s.V.rows());
    EXPECT_EQ(r.mesh.F, s.F);  // exactly the sphere again, in its order
    EXPECT_NO_THROW(validate_mesh(r.mesh.V, r.mesh.F));
    for (size_t k = 0; k < r.vertex_source.size(); ++k) EXPECT_EQ(r.vertex_source[k], static_cast<int>(k));
    EXPECT_EQ(r.face_source.size(), static_cast<size_t>(s.F.rows()));
    EXPECT_NE(
        r.summary().find("1 duplicate vertex merged, 1 zero-area or repeated-vertex face removed, "
                         "1 duplicate face removed, 1 smaller component (1 faces) removed, 3 unreferenced "
                         "vertices dropped"),
        std::string::npos)
        << r.summary();

    // Seeds of tests/fuzz/fuzz_canonical_form.cpp: byte 0 = base mesh (bit 0), repair (bit 1), method (bits
    // 2-4); then 8-byte edits. Seeds: each method untouched, a duplicated vertex with and without
    // repair, a face index out of range, a NaN and a 1e200 coordinate.
    for (int method = 0; method < 6; ++method)
        test::fuzz_seed("canonical_form", "method" + std::to_string(method),
                        std::string(1, char(method << 2)));
    const std::string dup = std::string("\x01\x05\x09\0\0\0\0\0", 8),
                      bad_index = std::string("\x02\x03\x01\x01\x40\x42\x0f\0", 8);
    test::fuzz_seed("canonical_form", "duplicate_vertex", std::string(1, char(1 << 2)) + dup);
    test::fuzz_seed("canonical_form", "duplicate_vertex_repaired", std::string(1, char((1 << 2) | 2)) + dup);
    test::fuzz_seed("canonical_form", "index_out_of_range", std::string(1, char(1 << 2)) + bad_index);
    test::fuzz_seed("canonical_form", "nan",
                    std::string(1, char(3 << 2)) + std::string("\x00\x02\x01\x06\0\0\0\0", 8));
    test::fuzz_seed("canonical_form", "huge",
                    std::string(1, char(1 << 2)) + std::string("\x00\x02\x01\x03\0\0\0\0", 8));
}

TEST(MeshRepair, AGoodMeshIsLeftAsItIsAndWhatCannotBeRepairedStaysAnError) {
    const Mesh s = make_torus(20, 10);
    const MeshRepair r = repair_mesh(s.V, s.F);
    EXPECT_FALSE(r.changed());
    EXPECT_EQ(r.mesh.V, s.V);
    EXPECT_EQ(r.mesh.F, s.F);
    EXPECT_NE(r.summary().find("nothing to repair"), std::string::npos);
    Eigen::MatrixXd V = s.V;
    V(3, 1) = std::nan("");
    const MeshRepair n = repair_mesh(V, s.F);  // NaN is not invented away
    EXPECT_NE(test::message_of([&] { validate_mesh(n.mesh.V, n.mesh.F); }).find("NaN"), std::string::npos);
    Eigen::MatrixXi F = s.F;
    F(2, 2) = -1;
    EXPECT_NE(test::message_of([&] { repair_mesh(s.V, F); }).find("out of range"), std::string::npos);
}
