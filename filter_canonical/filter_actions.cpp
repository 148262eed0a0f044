// SPDX-License-Identifier: GPL-3.0-or-later
#include "filter_actions.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/meshlab/meshlab_document.h"
#include "canonform/meshlab/vcg_bridge.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/selection.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/append.h>

#include <QFileInfo>

#include <map>
#include <optional>
#include <sstream>
#include <type_traits>
#include <variant>

namespace canonform::meshlab {

namespace {

MeshModel& current_mesh(MeshDocument& md) {
    if (md.mm() == nullptr) throw InputError("there is no current mesh");
    return *md.mm();
}

/// The mesh a filter computes on: the current mesh bridged, or with the "repair" parameter its
/// repaired copy (surface/mesh_repair.h; the summary is logged). The document itself is repaired
/// by commit_repair() only once the computation has succeeded, so a failure leaves it unchanged.
struct FilterInput {
    BridgedMesh<CMeshO> b;                      ///< what to compute on (repaired if asked)
    std::optional<surface::MeshRepair> repair;  ///< the repair, if it changed something
};

FilterInput filter_input(MeshModel& mm, const ParamValues& p, const ActionContext& ctx) {
    FilterInput in{to_eigen(mm.cm), {}};
    if (p.values.count("repair") &&
        p.get_bool("repair")) {  // scripts written before it have no "repair": off
        surface::MeshRepair r = surface::repair_mesh(in.b.V, in.b.F);
        ctx.log("'" + mm.label().toStdString() + "': " + r.summary());
        if (r.changed()) in.repair = std::move(r);
    }
    if (in.repair) {
        in.b.V = in.repair->mesh.V;
        in.b.F = in.repair->mesh.F;
    }
    return in;
}

/// Applies the repair of `in` (if any) to the current mesh - faces removed or rewired to the kept
/// copy of a duplicate vertex, vertices removed, vectors compacted, topology, normals and box
/// updated - and returns the current mesh bridged again: its rows are those of in.b.
BridgedMesh<CMeshO> commit_repair(MeshModel& mm, FilterInput& in) {
    if (!in.repair) return std::move(in.b);
    const surface::MeshRepair& r = *in.repair;
    CMeshO& m = mm.cm;
    std::vector<CMeshO::FacePointer> faces;
    for (auto& f : m.face)
        if (!f.IsD()) faces.push_back(&f);
    std::vector<char> keep_face(faces.size(), 0), keep_vertex(in.b.vertices.size(), 0);
    for (size_t k = 0; k < r.face_source.size(); ++k) {
        CMeshO::FacePointer f = faces[static_cast<size_t>(r.face_source[k])];
        keep_face[static_cast<size_t>(r.face_source[k])] = 1;
        for (int c = 0; c < 3; ++c)
            f->V(c) = in.b.vertices[static_cast<size_t>(
                r.vertex_source[static_cast<size_t>(r.mesh.F(static_cast<Eigen::Index>(k), c))])];
    }
    for (int v : r.vertex_source) keep_vertex[static_cast<size_t>(v)] = 1;
    for (size_t f = 0; f < faces.size(); ++f)
        if (!keep_face[f]) vcg::tri::Allocator<CMeshO>::DeleteFace(m, *faces[f]);
    for (size_t v = 0; v < keep_vertex.size(); ++v)
        if (!keep_vertex[v]) vcg::tri::Allocator<CMeshO>::DeleteVertex(m, *in.b.vertices[v]);
    vcg::tri::Allocator<CMeshO>::CompactEveryVector(m);
    if (vcg::tri::HasFFAdjacency(m)) vcg::tri::UpdateTopology<CMeshO>::FaceFace(m);
    if (vcg::tri::HasVFAdjacency(m)) vcg::tri::UpdateTopology<CMeshO>::VertexFace(m);
    vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(m);
    vcg::tri::UpdateBounding<CMeshO>::Box(m);
    BridgedMesh<CMeshO> out = to_eigen(m);
    if (out.V.rows() != r.mesh.V.rows() || out.F != r.mesh.F)
        throw NumericalError("internal error: the repaired document does not match the repaired mesh");
    return out;
}

/// Validates the mesh (InputError names any problem) and logs what the user should know about
/// an acceptable one: boundaries are allowed (eq. 8 treats their vertices) but change the result.
template <class Bridged>
void validate_and_note(const Bridged& b, const ActionContext& ctx) {
    const surface::MeshReport r = surface::validate_mesh(b.V, b.F);
    if (r.boundary_edges > 0) {
        std::ostringstream m;
        m << "note: the mesh is open (" << r.boundary_edges << " boundary edges, "
          << r.boundary_loops_vertices
          << " boundary vertices); their curvature uses pi instead of 2 pi (eq. 8)";
        ctx.log(m.str());
    }
}

/// Name of a new layer derived from `mm`: its file name without extension plus `suffix` (MeshLab
/// shows a label up to its first dot, so "fig.ply canonical form" would show as "fig").
QString layer_name(const MeshModel& mm, const char* suffix) {
    return QFileInfo(mm.label()).completeBaseName() + suffix;
}

/// The conformal factor of a bridged mesh, after validate_and_note().
template <class Bridged>
surface::ConformalFactorResult validated_conformal_factor(const Bridged& b, const ActionContext& ctx) {
    validate_and_note(b, ctx);
    surface::ConformalFactorOptions opt;
    opt.progress = ctx.progress;
    opt.validate = false;
    return surface::conformal_factor(b.V, b.F, opt);
}

/// The options of a parameter set from the filter's values of its parameters (checked: InputError
/// naming a value out of range).
template <class Options>
Options options_from(const ParameterSet<Options>& set, const ParamValues& p) {
    return set.read(p.texts(set.parameters()));
}

ActionOutputs conformal_factor_action(const FilterSpec&, MeshDocument& md, const ParamValues& p,
                                      const ActionContext& ctx) {
    MeshModel& mm = current_mesh(md);
    FilterInput in = filter_input(mm, p, ctx);
    const surface::ConformalFactorResult cf = validated_conformal_factor(in.b, ctx);
    const bool normalized = p.get_bool("normalize");
    const auto b = commit_repair(mm, in);  // everything computed: now change the document
    mm.updateDataMask(MeshModel::MM_VERTQUALITY);
    write_quality(b, normalized ? cf.normalized : cf.raw);
    if (p.get_bool("colorize")) {
        mm.updateDataMask(MeshModel::MM_VERTCOLOR);
        vcg::tri::UpdateColor<CMeshO>::PerVertexQualityRamp(mm.cm);
    }
    std::ostringstream log;
    log << "Conformal factor of '" << mm.label().toStdString() << "' (" << b.V.rows()
        << " vertices): raw range [" << cf.raw.minCoeff() << ", " << cf.raw.maxCoeff()
        << "], relative residual " << cf.residual << "; stored "
        << (normalized ? "normalised to [0, 1]" : "raw") << " in the vertex quality";
    ctx.log(log.str());
    return {{"vertices", int(b.V.rows())},
            {"min", cf.raw.minCoeff()},
            {"max", cf.raw.maxCoeff()},
            {"residual", cf.residual}};
}

ActionOutputs feature_points_action(const FilterSpec&, MeshDocument& md, const ParamValues& p,
                                    const ActionContext& ctx) {
    MeshModel& mm = current_mesh(md);
    const surface::FeaturePointOptions opt = options_from(surface::feature_point_parameters(), p);
    const int ring = opt.ring;
    FilterInput in = filter_input(mm, p, ctx);
    const surface::ConformalFactorResult cf = validated_conformal_factor(in.b, ctx);
    const surface::FeaturePoints fp = surface::feature_points(in.b.F, cf.normalized, opt);

    // Everything computed: now change the document.
    const auto b = commit_repair(mm, in);
    vcg::tri::UpdateSelection<CMeshO>::VertexClear(mm.cm);
    for (int v : fp.indices) b.vertices[static_cast<size_t>(v)]->SetS();
    mm.updateDataMask(MeshModel::MM_VERTQUALITY);
    write_quality(b, cf.normalized);
    if (p.get_bool("add_layer")) {
        MeshModel* layer = md.addNewMesh("", layer_name(mm, " feature points"), false);
        layer->updateDataMask(MeshModel::MM_VERTQUALITY);
        auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(layer->cm, fp.indices.size());
        for (int v : fp.indices) {
            vi->P() = b.vertices[static_cast<size_t>(v)]->P();
            vi->Q() = static_cast<CMeshO::VertexType::QualityType>(cf.normalized(v));
            ++vi;
        }
        vcg::tri::UpdateBounding<CMeshO>::Box(layer->cm);
    }
    std::ostringstream log;
    log << "Feature points of '" << mm.label().toStdString() << "': " << fp.indices.size() << " selected ("
        << fp.num_maxima << " local maxima over the " << ring << "-ring of " << fp.total_maxima << " found, "
        << fp.num_random << " random; target ceil(sqrt(" << b.V.rows()
        << ")) = " << surface::sqrt_count(int(b.V.rows())) << ")";
    ctx.log(log.str());
    return {{"selected", int(fp.indices.size())},
            {"maxima", int(fp.num_maxima)},
            {"random", int(fp.num_random)},
            {"target", int(surface::sqrt_count(int(b.V.rows())))}};
}

/// Writes a canonical form X (#V x 3, rows as in `b`) into a new layer named after `mm` (or in
/// place), with the quality and selection given; recomputes normals and bounding box.
template <class Bridged>
void write_canonical_form(MeshDocument& md, MeshModel& mm, const Bridged& b, const Eigen::MatrixXd& X,
                          const Eigen::VectorXd* quality, const std::vector<int>* selected, bool new_layer) {
    MeshModel* target = &mm;
    if (new_layer) {
        target = md.addNewMesh("", layer_name(mm, " canonical form"), false);
        target->updateDataMask(&mm);
        vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(target->cm, mm.cm);
    }
    const auto out = to_eigen(target->cm);
    if (out.V.rows() != b.V.rows())
        throw NumericalError("internal error: the new layer does not have the source's vertices");
    write_positions(out, X);
    if (quality) {
        target->updateDataMask(MeshModel::MM_VERTQUALITY);
        write_quality(out, *quality);
    }
    if (selected) {
        vcg::tri::UpdateSelection<CMeshO>::VertexClear(target->cm);
        for (int v : *selected) out.vertices[static_cast<size_t>(v)]->SetS();
    }
    vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(target->cm);
    vcg::tri::UpdateBounding<CMeshO>::Box(target->cm);
}

/// The settings of `method` from the filter's parameters of the same names (every parameter of
/// the method is one of its filter's: canonical_filter_table.cpp).
canonical::MethodSettings method_settings(const canonical::CanonicalMethod& method, const ParamValues& p) {
    return method.settings(p.texts(method.parameters));
}

/// A filter of a method family ("Euclidean canonical form": `variant`, "Geodesic canonical form":
/// `method`): the method of the registry its enum (its first parameter) names, with the filter's
/// values of the method's parameters; its result in a new layer or in place.
template <canonical::MethodFamily family>
ActionOutputs canonical_form_action(const FilterSpec& spec, MeshDocument& md, const ParamValues& p,
                                    const ActionContext& ctx) {
    MeshModel& mm = current_mesh(md);
    const auto methods = canonical::canonical_methods_of(family);
    const Parameter& selector = spec.params.front();
    const int choice = p.get_int(selector.name());
    if (choice < 0 || choice >= static_cast<int>(methods.size()))
        throw InputError(selector.name() + " must be " + selector.requirement() + ", got the index " +
                         std::to_string(choice));
    const canonical::CanonicalMethod& method = *methods[static_cast<size_t>(choice)];
    const canonical::MethodSettings settings = method_settings(method, p);

    FilterInput in = filter_input(mm, p, ctx);
    validate_and_note(in.b, ctx);
    canonical::MethodContext context;
    context.progress = ctx.progress;
    context.validate = false;  // validate_and_note() above
    const canonical::CanonicalForm r = method.run(in.b.V, in.b.F, settings, context);
    if (!r.V.allFinite()) throw NumericalError(method.name + " gave a form with NaN or infinite coordinates");
    const auto b = commit_repair(mm, in);  // everything computed: now change the document
    write_canonical_form(md, mm, b, r.V, r.quality.size() ? &r.quality : nullptr,
                         r.features.empty() ? nullptr : &r.features, p.get_bool("new_layer"));
    ctx.log(spec.name + " of '" + mm.label().toStdString() + "': " + r.description);
    ActionOutputs out;
    for (const auto& [key, value] : r.summary)
        if (!std::holds_alternative<std::string>(value))
            std::visit(
                [&out, k = key](const auto& v) {
                    if constexpr (!std::is_same_v<std::decay_t<decltype(v)>, std::string>) out[k] = v;
                },
                value);
    return out;
}

using Action = ActionOutputs (*)(const FilterSpec&, MeshDocument&, const ParamValues&, const ActionContext&);

/// The action of every filter of the table, by Python name. A new filter: its table row
/// (canonical_filter_table.cpp), its action above and one line here.
const std::map<std::string, Action>& actions() {
    static const std::map<std::string, Action> a = {
        {"compute_conformal_factor", conformal_factor_action},
        {"compute_feature_points", feature_points_action},
        {"generate_euclidean_canonical_form", canonical_form_action<canonical::MethodFamily::Euclidean>},
        {"generate_geodesic_canonical_form", canonical_form_action<canonical::MethodFamily::Geodesic>},
    };
    return a;
}

}  // namespace

ActionOutputs apply_filter_action(int id, MeshDocument& md, const ParamValues& params,
                                  const ActionContext& context) {
    const FilterSpec& spec = filter_spec(filter_table(), id);
    const auto it = actions().find(spec.python_name);
    if (it == actions().end()) throw InputError("filter '" + spec.name + "' has no action");
    return it->second(spec, md, params, context);
}

}  // namespace canonform::meshlab
