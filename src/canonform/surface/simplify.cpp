// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/simplify.h"

#include <mutex>

// vcglib's quadric code trips GCC 12's -Wmaybe-uninitialized inside its own headers.
#if !defined(__clang__)  // (no such warning in clang)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "canonform/common/errors.h"

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/local_optimization.h>
#include <vcg/complex/algorithms/local_optimization/tri_edge_collapse_quadric.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>
#include <vcg/simplex/face/component_ep.h>

#include <string>

namespace canonform::surface {

namespace {

class SVertex;
class SFace;
struct STypes : public vcg::UsedTypes<vcg::Use<SVertex>::AsVertexType, vcg::Use<SFace>::AsFaceType> {};
class SVertex : public vcg::Vertex<STypes, vcg::vertex::VFAdj, vcg::vertex::Coord3d, vcg::vertex::Normal3d,
                                   vcg::vertex::Mark, vcg::vertex::Qualityd, vcg::vertex::BitFlags> {};
class SFace : public vcg::Face<STypes, vcg::face::VFAdj, vcg::face::VertexRef, vcg::face::Normal3d,
                               vcg::face::BitFlags> {};
class SMesh : public vcg::tri::TriMesh<std::vector<SVertex>, std::vector<SFace>> {};

using QuadricTemp = vcg::SimpleTempData<SMesh::VertContainer, vcg::math::Quadric<double>>;

/// Per-vertex quadrics kept outside the vertex, as MeshLab's filter does.
struct QHelper {
    static void Init() {}
    static vcg::math::Quadric<double>& Qd(SVertex& v) { return TD()[v]; }
    static vcg::math::Quadric<double>& Qd(SVertex* v) { return TD()[*v]; }
    static SVertex::ScalarType W(SVertex*) { return 1.0; }
    static SVertex::ScalarType W(SVertex&) { return 1.0; }
    static void Merge(SVertex&, SVertex const&) {}
    static QuadricTemp*& TDp() {
        static QuadricTemp* td = nullptr;
        return td;
    }
    static QuadricTemp& TD() { return *TDp(); }
};

using VertexPair = vcg::tri::BasicVertexPair<SVertex>;

class Collapse : public vcg::tri::TriEdgeCollapseQuadric<SMesh, VertexPair, Collapse, QHelper> {
public:
    using TECQ = vcg::tri::TriEdgeCollapseQuadric<SMesh, VertexPair, Collapse, QHelper>;
    Collapse(const VertexPair& p, int i, vcg::BaseParameterClass* pp) : TECQ(p, i, pp) {}
};

}  // namespace

Mesh simplify_mesh(const Mesh& mesh, int target_vertices) {
    if (target_vertices < 10) throw InputError("the simplification target must be at least 10 vertices");
    if (target_vertices >= mesh.V.rows())
        throw InputError("the mesh has " + std::to_string(mesh.V.rows()) +
                         " vertices, not more than the target " + std::to_string(target_vertices));
    if (mesh.F.rows() == 0) throw InputError("cannot simplify a point cloud");
    // vcglib's edge collapse keeps state in function-local statics (the quadric table pointer
    // above, TriEdgeCollapse::GlobalMark() and statistics): one simplification at a time
    // (two at once, as `canonform retrieve --simplify` on two threads did, crash).
    static std::mutex one_at_a_time;
    std::lock_guard<std::mutex> lock(one_at_a_time);
    SMesh m;
    auto vi = vcg::tri::Allocator<SMesh>::AddVertices(m, static_cast<size_t>(mesh.V.rows()));
    for (Eigen::Index k = 0; k < mesh.V.rows(); ++k, ++vi)
        vi->P() = vcg::Point3d(mesh.V(k, 0), mesh.V(k, 1), mesh.V(k, 2));
    auto fi = vcg::tri::Allocator<SMesh>::AddFaces(m, static_cast<size_t>(mesh.F.rows()));
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f, ++fi)
        for (int c = 0; c < 3; ++c) fi->V(c) = &m.vert[static_cast<size_t>(mesh.F(f, c))];
    vcg::tri::UpdateTopology<SMesh>::VertexFace(m);
    vcg::tri::UpdateNormal<SMesh>::PerFace(m);
    vcg::tri::UpdateBounding<SMesh>::Box(m);

    vcg::tri::TriEdgeCollapseQuadricParameter pp;  // MeshLab's defaults
    pp.QualityThr = 0.3;
    pp.PreserveTopology = true;
    pp.OptimalPlacement = true;
    pp.QualityCheck = true;
    pp.NormalCheck = true;
    pp.NormalThrRad = M_PI / 4.0;
    vcg::math::Quadric<double> zero;
    zero.SetZero();
    QuadricTemp td(m.vert, zero);
    QHelper::TDp() = &td;
    const auto target_faces =
        static_cast<int>(static_cast<double>(mesh.F.rows()) * target_vertices / mesh.V.rows());
    vcg::LocalOptimization<SMesh> session(m, &pp);
    session.Init<Collapse>();
    session.SetTargetSimplices(target_faces);
    while (session.DoOptimization() && m.fn > target_faces) {
    }
    session.Finalize<Collapse>();
    QHelper::TDp() = nullptr;
    vcg::tri::Clean<SMesh>::RemoveUnreferencedVertex(m);
    vcg::tri::Allocator<SMesh>::CompactEveryVector(m);

    Mesh out;
    out.V.resize(m.vn, 3);
    for (int k = 0; k < m.vn; ++k)
        for (int c = 0; c < 3; ++c) out.V(k, c) = m.vert[static_cast<size_t>(k)].P()[c];
    out.F.resize(m.fn, 3);
    for (int f = 0; f < m.fn; ++f)
        for (int c = 0; c < 3; ++c)
            out.F(f, c) = static_cast<int>(m.face[static_cast<size_t>(f)].V(c) - &m.vert[0]);
    return out;
}

}  // namespace canonform::surface
