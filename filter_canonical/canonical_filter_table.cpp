// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonical_filter_table.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/numerics/smacof.h"

namespace canonform::meshlab {

namespace {

const char* kCitation =
    "<br><br>P. Pickup, X. Sun, P. L. Rosin, R. R. Martin, <b>\"Euclidean-distance-based canonical "
    "forms for non-rigid 3D shape retrieval\"</b>, Pattern Recognition 48(8), 2015.";

// Parameters several filters share (one keyword, default and help); functions rather than globals, so
// that the table may be built during another translation unit's static initialisation.
ParamSpec repair_param() {
    return {"repair", ParamKind::Bool, 0, "Repair the mesh first",
            "Off (default): refuse a mesh with zero-area or duplicate faces, duplicate or unreferenced "
            "vertices or several components, naming the problem. On: merge duplicate vertices, remove "
            "zero-area and duplicate faces, keep the largest component, drop unreferenced vertices - in "
            "the current mesh, once the computation has succeeded - and log what changed.", {}};
}
ParamSpec new_layer_param() {
    return {"new_layer", ParamKind::Bool, 1, "Result in a new layer",
            "Put the canonical form in a new layer named after the source mesh; off: replace the "
            "vertex positions of the current mesh.", {}};
}
ParamSpec tolerance_param() {
    return {"tolerance", ParamKind::Float, 1e-5, "Tolerance",
            "SMACOF stops when the relative stress decrease of an iteration falls below this.", {}};
}

/// The labels of a filter's methods (its enum), from the registry.
std::vector<std::string> method_labels(canonical::MethodFamily family) {
    std::vector<std::string> labels;
    for (const canonical::CanonicalMethod* m : canonical::canonical_methods_of(family)) labels.push_back(m->label);
    return labels;
}

/// The enum index of method `name` among its family's methods.
double method_index(canonical::MethodFamily family, const std::string& name) {
    const auto methods = canonical::canonical_methods_of(family);
    for (size_t k = 0; k < methods.size(); ++k)
        if (methods[k]->name == name) return static_cast<double>(k);
    return 0;
}

/// The enum index of the default SMACOF acceleration.
double acceleration_index() {
    const auto names = numerics::smacof_acceleration_names();
    for (size_t k = 0; k < names.size(); ++k)
        if (names[k] == to_string(numerics::kDefaultSmacofAcceleration)) return static_cast<double>(k);
    return 0;
}

/// The Euclidean filter's acceleration parameter (the geodesic filter's says "least squares only").
ParamSpec acceleration_param() {
    return {"acceleration", ParamKind::Enum, acceleration_index(), "SMACOF acceleration",
            "none: plain Guttman steps; relaxed: X + 2(G(X) - X) (de Leeuw); rre / mpe: reduced-rank / "
            "minimal-polynomial vector extrapolation (Rosman et al. 2008); anderson: Anderson acceleration. "
            "A step that would raise the stress is replaced by the plain step.",
            numerics::smacof_acceleration_names()};
}

}  // namespace

std::vector<FilterSpec> make_filter_table() {
    using K = ParamKind;
    std::vector<FilterSpec> t;
    t.push_back({int(FilterId::ConformalFactor), "Conformal factor", "compute_conformal_factor",
                 "conformal_factor.mlx", FilterKind::Quality,
                 prose(R"(Computes the discrete conformal factor of every vertex (Ben-Chen and Gotsman 2008;
                 eqs. 7-9 of Pickup et al. 2015): the solution of L phi = K^T - K^0 with the cotangent
                 Laplacian, the angle-deficit curvature K^0 and the area-proportional target curvature K^T. It
                 is pose invariant and largest at the extremities of the shape. Stored in the vertex
                 quality.)"),
                 {{"normalize", K::Bool, 1, "Normalise to [0, 1]",
                   "Store (phi - min) / (max - min) instead of the raw conformal factor (mean zero).", {}},
                  {"colorize", K::Bool, 1, "Colour vertices",
                   "Also colour the vertices by the conformal factor (red-green-blue ramp).", {}},
                  repair_param()},
                 kVertexQuality | kVertexColor, kVertexQuality | kVertexColor | kTopology | kNormals});
    t.push_back({int(FilterId::FeaturePoints), "Feature points", "compute_feature_points", "feature_points.mlx",
                 FilterKind::Selection,
                 prose(R"(Selects the feature points of Pickup et al. 2015: the ceil(sqrt(N)) vertices with
                 the largest conformal factor among those that are local maxima over their k-ring. Optionally
                 tops the set up to ceil(sqrt(N)) with seeded random vertices (the paper's variant A) and adds
                 a point-cloud layer of the points with the conformal factor as quality.)"),
                 {{"ring", K::Int, 2, "Ring size (k)",
                   "A feature point is greater than every vertex of its k-ring (1, 2 or 3; the paper uses 2).", {}},
                  {"fill", K::Enum, 0, "Fill",
                   "none: local maxima only (variant N); random: add seeded random vertices up to ceil(sqrt(N)) "
                   "(variant A).",
                   {"none", "random"}},
                  {"seed", K::Int, 0, "Random seed", "Seed of the random fill.", {}},
                  {"add_layer", K::Bool, 0, "Add a point-cloud layer",
                   "Add a new layer holding the feature points, with the conformal factor as vertex quality.", {}},
                  repair_param()},
                 kVertexQuality, kVertexQuality | kVertexSelection | kTopology | kNormals});
    t.push_back({int(FilterId::EuclideanCanonicalForm), "Euclidean canonical form", "generate_euclidean_canonical_form",
                 "euclidean_canonical_form.mlx", FilterKind::Smoothing,
                 prose(R"(Computes the pose-invariant canonical form of Pickup et al. 2015: SMACOF keeps the
                 mesh edge lengths (weight beta / length^2) while pushing every pair of feature points to
                 distance alpha (weight: the mean of their normalised conformal factors), starting from the
                 mesh scaled to unit radius. Variant A adds random feature points up to ceil(sqrt(N)) (beta =
                 10); variant N normalises both weight groups (eq. 10, beta = 130). The result keeps the
                 input's faces, vertex order and units; feature points are selected and the conformal factor
                 is stored in the vertex quality.)"),
                 {{"variant", K::Enum, method_index(canonical::MethodFamily::Euclidean, "euclidean-N"), "Variant",
                   "A: additional random feature points (beta 10); N: normalised weightings (eq. 10, beta 130).",
                   method_labels(canonical::MethodFamily::Euclidean)},
                  {"alpha", K::Float, 10, "Alpha", "Target distance of every feature-point pair, in "
                   "units of the mesh radius (the paper uses 10).", {}},
                  {"beta", K::Float, 0, "Beta (0 = variant default)",
                   "Edge-length preservation weight; 0 uses 10 for variant A and 130 for variant N.", {}},
                  {"ring", K::Int, 2, "Ring size (k)", "k-ring of the conformal-factor maxima (1, 2 or 3).", {}},
                  {"seed", K::Int, 0, "Random seed", "Seed of variant A's random feature points.", {}},
                  tolerance_param(),
                  {"max_iterations", K::Int, 1000, "Maximum iterations", "SMACOF iteration cap.", {}},
                  acceleration_param(),
                  new_layer_param(),
                  repair_param()},
                 kVertexQuality, kVertexQuality | kVertexSelection | kVertexCoordinates | kNormals | kTopology});
    t.push_back({int(FilterId::GeodesicCanonicalForm), "Geodesic canonical form", "generate_geodesic_canonical_form",
                 "geodesic_canonical_form.mlx", FilterKind::Smoothing,
                 prose(R"(Computes the canonical form of Elad and Kimmel (IEEE TPAMI 2003), the baseline of
                 Pickup et al. 2015: all-pairs geodesic distances by fast marching, embedded in 3D by MDS -
                 least squares (SMACOF, all pairs), classical, or fast (landmark) MDS. Its memory grows like
                 N^2 and its time like N^2 log N: the filter estimates both first and refuses, naming them,
                 above the limits below. Same output conventions as 'Euclidean canonical form'.)"),
                 {{"method", K::Enum, method_index(canonical::MethodFamily::Geodesic, "geodesic-ls"), "MDS method",
                   "least squares: SMACOF on all pairs (Elad-Kimmel, the paper's LS); classical: double "
                   "centring and the top three eigenvectors (C); fast: landmark MDS (F).",
                   method_labels(canonical::MethodFamily::Geodesic)},
                  tolerance_param(),
                  {"max_iterations", K::Int, 500, "Maximum iterations", "SMACOF iteration cap.", {}},
                  {"acceleration", K::Enum, acceleration_index(), "SMACOF acceleration",
                   "Least squares only. none: plain Guttman steps; relaxed: X + 2(G(X) - X) (de Leeuw); rre / mpe: reduced-rank / "
                   "minimal-polynomial vector extrapolation (Rosman et al. 2008); anderson: Anderson acceleration. "
                   "A step that would raise the stress is replaced by the plain step.",
                   numerics::smacof_acceleration_names()},
                  {"max_memory_gib", K::Float, 4, "Memory limit (GiB)",
                   "Refuse meshes whose estimated memory (an N x N distance matrix) exceeds this.", {}},
                  {"max_seconds", K::Float, 600, "Time limit (s)",
                   "Refuse meshes whose estimated computing time exceeds this.", {}},
                  new_layer_param(),
                  repair_param()},
                 kNothing, kVertexCoordinates | kNormals | kTopology});
    for (auto& f : t) f.info += kCitation;
    return t;
}

const std::vector<FilterSpec>& filter_table() {
    static const std::vector<FilterSpec> table = make_filter_table();
    return table;
}

}  // namespace canonform::meshlab
