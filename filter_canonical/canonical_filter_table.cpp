// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonical_filter_table.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"

namespace canonform::meshlab {

namespace {

const char* kCitation =
    "<br><br>P. Pickup, X. Sun, P. L. Rosin, R. R. Martin, <b>\"Euclidean-distance-based canonical "
    "forms for non-rigid 3D shape retrieval\"</b>, Pattern Recognition 48(8), 2015.";

// The parameters only these filters have (what happens in the MeshLab document); the others are
// the library's definitions. Functions rather than globals, so that the table may be built during
// another translation unit's static initialisation.
Parameter colorize_parameter() {
    return Parameter::flag("colorize")
        .default_value("true")
        .label("Colour vertices")
        .help("also colour the vertices by the conformal factor (red-green-blue ramp)");
}
Parameter add_layer_parameter() {
    return Parameter::flag("add_layer")
        .label("Add a point-cloud layer")
        .help("add a new layer holding the feature points, with the conformal factor as vertex quality");
}
Parameter new_layer_parameter() {
    return Parameter::flag("new_layer")
        .default_value("true")
        .label("Result in a new layer")
        .help(
            "put the canonical form in a new layer named after the source mesh; off: replace the vertex "
            "positions of the current mesh");
}

/// The parameters of the filter of a method family: `selector`, the enum of the family's methods
/// (their labels; default: the family's default method), then every parameter of those methods
/// (method_registry.h; one a method ignores is noted in its help), then `extra`.
std::vector<Parameter> method_filter_parameters(canonical::MethodFamily family, const std::string& selector,
                                                const std::string& label,
                                                const std::vector<Parameter>& extra) {
    const std::vector<const canonical::CanonicalMethod*> methods = canonical::canonical_methods_of(family);
    std::vector<std::string> labels;
    std::string help;
    for (const canonical::CanonicalMethod* m : methods) {
        labels.push_back(m->label);
        help += (help.empty() ? "" : "; ") + m->label + ": " + m->help;
    }
    std::vector<Parameter> out = {Parameter::choice(selector, labels)
                                      .label(label)
                                      .help(help)
                                      .default_value(canonical::default_method_of(family).label)};
    for (Parameter p : canonical::family_parameters(family)) {
        std::vector<std::string> users;
        for (const canonical::CanonicalMethod* m : methods) {
            const Parameter* q = m->parameter(p.name());
            if (q && q->affects_result()) users.push_back(m->label);
        }
        if (!users.empty() && users.size() < methods.size() && p.affects_result()) {
            std::string who;
            for (const auto& u : users) who += (who.empty() ? "" : ", ") + u;
            p.help(p.help() + " (" + who + " only)");
        }
        out.push_back(std::move(p));
    }
    return concat(std::move(out), extra);
}

}  // namespace

std::vector<FilterSpec> make_filter_table() {
    std::vector<FilterSpec> t;
    t.push_back(
        FilterSpec("Conformal factor", "compute_conformal_factor", FilterKind::Quality)
            .with_info(
                prose(R"(Computes the discrete conformal factor of every vertex (Ben-Chen and Gotsman 2008;
                 eqs. 7-9 of Pickup et al. 2015): the solution of L phi = K^T - K^0 with the cotangent
                 Laplacian, the angle-deficit curvature K^0 and the area-proportional target curvature K^T. It
                 is pose invariant and largest at the extremities of the shape. Stored in the vertex
                 quality.)"))
            .with_params({surface::normalize_parameter(), colorize_parameter(), surface::repair_parameter()})
            .with_needs(kVertexQuality | kVertexColor)
            .with_changes(kVertexQuality | kVertexColor | kTopology | kNormals));
    t.push_back(FilterSpec("Feature points", "compute_feature_points", FilterKind::Selection)
                    .with_info(prose(
                        R"(Selects the feature points of Pickup et al. 2015: the ceil(sqrt(N)) vertices with
                 the largest conformal factor among those that are local maxima over their k-ring. Optionally
                 tops the set up to ceil(sqrt(N)) with seeded random vertices (the paper's variant A) and adds
                 a point-cloud layer of the points with the conformal factor as quality.)"))
                    .with_params(concat(surface::feature_point_parameters().parameters(),
                                        {add_layer_parameter(), surface::repair_parameter()}))
                    .with_needs(kVertexQuality)
                    .with_changes(kVertexQuality | kVertexSelection | kTopology | kNormals));
    t.push_back(
        FilterSpec("Euclidean canonical form", "generate_euclidean_canonical_form", FilterKind::Smoothing)
            .with_info(
                prose(R"(Computes the pose-invariant canonical form of Pickup et al. 2015: SMACOF keeps the
                 mesh edge lengths (weight beta / length^2) while pushing every pair of feature points to
                 distance alpha (weight: the mean of their normalised conformal factors), starting from the
                 mesh scaled to unit radius. Variant A adds random feature points up to ceil(sqrt(N)) (beta =
                 10); variant N normalises both weight groups (eq. 10, beta = 130). The result keeps the
                 input's faces, vertex order and units; feature points are selected and the conformal factor
                 is stored in the vertex quality.)"))
            .with_params(method_filter_parameters(canonical::MethodFamily::Euclidean, "variant", "Variant",
                                                  {new_layer_parameter(), surface::repair_parameter()}))
            .with_needs(kVertexQuality)
            .with_changes(kVertexQuality | kVertexSelection | kVertexCoordinates | kNormals | kTopology));
    t.push_back(
        FilterSpec("Geodesic canonical form", "generate_geodesic_canonical_form", FilterKind::Smoothing)
            .with_info(
                prose(R"(Computes the canonical form of Elad and Kimmel (IEEE TPAMI 2003), the baseline of
                 Pickup et al. 2015: all-pairs geodesic distances by fast marching, embedded in 3D by MDS -
                 least squares (SMACOF, all pairs), classical, or fast (landmark) MDS. Its memory grows like
                 N^2 and its time like N^2 log N: the filter estimates both first and refuses, naming them,
                 above the limits below. Same output conventions as 'Euclidean canonical form'.)"))
            .with_params(method_filter_parameters(canonical::MethodFamily::Geodesic, "method", "MDS method",
                                                  {new_layer_parameter(), surface::repair_parameter()}))
            .with_needs(kNothing)
            .with_changes(kVertexCoordinates | kNormals | kTopology));
    for (auto& f : t) f.info += kCitation;
    number_filters(t);
    return t;
}

const std::vector<FilterSpec>& filter_table() {
    static const std::vector<FilterSpec> table = make_filter_table();
    return table;
}

}  // namespace canonform::meshlab
