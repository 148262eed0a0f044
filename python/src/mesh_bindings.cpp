// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module: meshes - files, conformal factor, feature points, canonical forms (any
// method of the registry), simplification, repair, procedural figures.
#include "bindings.h"
#include "support.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/surface/simplify.h"

#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <variant>
#include <vector>

namespace canonform::python {

namespace {

using Clock = std::chrono::steady_clock;

/// A parameter value from Python as the text the tool and method specs use: int as written, a
/// float so that strtod gives the same double back (17 significant digits), str as is.
std::string parameter_text(const std::string& name, const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "True" : "False";  // refused by the check
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (PyIndex_Check(v.ptr())) return py::str(py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr())));
    if (PyFloat_Check(v.ptr()) || py::hasattr(v, "__float__")) {
        const double d = py::float_(py::reinterpret_borrow<py::object>(v));
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", d);
        return buf;
    }
    throw InputError(name + " must be a number or a word, got " +
                     py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>());
}

py::object summary_value(const canonical::SummaryValue& v) {
    return std::visit(
        [](const auto& x) -> py::object {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, std::string>)
                return text(x);
            else
                return py::cast(x);
        },
        v);
}

/// Checks an integer against a parameter of the registry (its range is defined there once).
void check_as(const char* method, const char* parameter, const std::string& value) {
    const Parameter* p = canonical::canonical_method(method).parameter(parameter);
    if (p) p->check(value);
}

py::tuple read_mesh(const py::object& path, bool with_quality) {
    const std::string p = path_in(path);
    Call call;
    io::MeshFile f = call.run([&] { return io::read_mesh_file(p); });
    if (with_quality) return py::make_tuple(array_out(f.mesh.V), array_out(f.mesh.F), array_out(f.quality));
    return py::make_tuple(array_out(f.mesh.V), array_out(f.mesh.F));
}

void write_mesh(const py::object& path, const py::object& V, const py::object& F, const py::object& quality) {
    const std::string p = path_in(path);
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F, "F", true);
    Eigen::VectorXd q;
    if (!quality.is_none()) {
        q = vector_in(quality, "quality");
        if (q.size() != v.rows())
            throw InputError("quality has " + std::to_string(q.size()) + " values for " + std::to_string(v.rows()) +
                             " vertices");
    }
    Call call;
    call.run([&] { io::write_mesh(p, v, f, q); });
}

py::array_t<double> conformal(const py::object& V, const py::object& F, bool normalize, const py::object& progress) {
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call(progress);
    surface::ConformalFactorOptions o;
    o.progress = call.progress();
    const surface::ConformalFactorResult r = call.run([&] { return surface::conformal_factor(v, f, o); });
    return array_out(normalize ? r.normalized : r.raw);
}

py::array_t<std::int64_t> features(const py::object& V, const py::object& F, int ring, const std::string& fill,
                                   long long seed) {
    check_as("euclidean-N", "ring", std::to_string(ring));
    check_as("euclidean-A", "seed", std::to_string(seed));
    surface::FeaturePointOptions o;
    o.ring = ring;
    if (fill == "none")
        o.fill = surface::FeatureFill::None;
    else if (fill == "random")
        o.fill = surface::FeatureFill::Random;
    else
        throw InputError("fill must be 'none' or 'random', got '" + fill + "'");
    o.seed = static_cast<std::uint64_t>(seed);
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call;
    const surface::FeaturePoints fp = call.run([&] {
        surface::ConformalFactorOptions co;
        co.progress = call.interrupt_only();
        return surface::feature_points(f, surface::conformal_factor(v, f, co).normalized, o);
    });
    return indices_out(fp.indices);
}

std::tuple<py::array_t<double>, py::dict> canonical(const py::object& V, const py::object& F, const std::string& method_name, int threads,
                    const py::object& progress, const py::kwargs& params) {
    const auto t0 = Clock::now();
    canonical::MethodSpec spec;
    spec.name = method_name;
    const canonical::CanonicalMethod& method = canonical::canonical_method(spec.name);  // InputError listing the names
    for (const auto& [key, value] : params) {
        const std::string k = py::str(key);
        spec.given.emplace_back(k, parameter_text(k, value));
    }
    const canonical::MethodSettings settings = spec.settings();  // every name and value checked by the registry
    if (threads < 0 || threads > 1024) throw InputError("threads must be between 0 and 1024, got " + std::to_string(threads));
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call(progress);
    canonical::MethodContext context;
    context.threads = threads;
    context.progress = call.progress();
    context.validate = false;  // validated just before, as the tool does
    const canonical::CanonicalForm r = call.run([&] {
        surface::validate_mesh(v, f);
        return method.run(v, f, settings, context);
    });
    if (!r.V.allFinite())
        throw NumericalError("method " + method.name + " gave a form with NaN or infinite coordinates");
    // The tool's --json summary: the mesh, the method's summary in its order, the time.
    py::dict info;
    info["vertices"] = v.rows();
    info["faces"] = f.rows();
    for (const auto& [key, value] : r.summary) info[text(key)] = summary_value(value);
    info["total_seconds"] = std::chrono::duration<double>(Clock::now() - t0).count();
    return {array_out(r.V), info};
}

/// For bench/python_bench.py: seconds of the C++ call canonical() makes (the registry's run() on the
/// library's matrices, validating first), timed in C++ with the GIL held and no progress function -
/// what a C++ program pays, next to which the module's overhead is measured call by call.
double cpp_call_seconds(const py::object& V, const py::object& F, const std::string& method_name) {
    const canonical::CanonicalMethod& method = canonical::canonical_method(method_name);
    const canonical::MethodSettings settings = method.settings();
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    canonical::MethodContext context;
    context.threads = 1;
    const auto t0 = Clock::now();
    const canonical::CanonicalForm r = method.run(v, f, settings, context);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    if (r.V.rows() != v.rows()) throw NumericalError("unexpected form size");
    return seconds;
}

std::vector<py::dict> methods() {
    std::vector<py::dict> out;
    for (const canonical::CanonicalMethod* method : canonical::canonical_methods()) {
        const canonical::CanonicalMethod& m = *method;
        py::list params;
        for (const Parameter& p : m.parameters) {
            py::dict d;
            d["name"] = p.name();
            d["default"] = p.default_value();
            d["help"] = text(p.help());
            d["min"] = p.min();
            d["max"] = p.max();
            d["integer"] = p.type() == ParameterType::Int;
            d["choices"] = p.choices();
            d["zero_means_default"] = p.zero_means_default();
            params.append(d);
        }
        py::dict d;
        d["name"] = m.name;
        d["family"] = m.family == canonical::MethodFamily::Euclidean ? "euclidean"
                      : m.family == canonical::MethodFamily::Geodesic ? "geodesic"
                                                           : "none";
        d["help"] = text(m.help);
        d["parameters"] = params;
        out.push_back(d);
    }
    return out;
}

std::tuple<py::array_t<double>, py::array_t<std::int32_t>> simplify(const py::object& V, const py::object& F,
                                                                     int vertices) {
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call;
    const Mesh s = call.run([&] {
        surface::validate_mesh(v, f);
        return surface::simplify_mesh(Mesh{v, f}, vertices);
    });
    return {array_out(s.V), array_out(s.F)};
}

std::tuple<py::array_t<double>, py::array_t<std::int32_t>, py::str> repair(const py::object& V, const py::object& F) {
    const Eigen::MatrixXd v = vertices_in(V);
    const Eigen::MatrixXi f = faces_in(F);
    Call call;
    const surface::MeshRepair r = call.run([&] { return surface::repair_mesh(v, f); });
    return {array_out(r.mesh.V), array_out(r.mesh.F), text(r.summary())};
}

std::tuple<py::array_t<double>, py::array_t<std::int32_t>> figure(int vertices, int pose, const std::string& body) {
    if (vertices < 500 || vertices > 2000000)
        throw InputError("vertices must be between 500 and 2000000, got " + std::to_string(vertices));
    if (pose < 0) throw InputError("pose must be 0 or more, got " + std::to_string(pose));
    procedural::FigureProportions proportions;
    try {
        proportions = procedural::figure_class(body);
    } catch (const std::invalid_argument& e) {
        throw InputError(e.what());
    }
    Call call;
    const procedural::Figure fig = call.run([&] { return procedural::make_figure(vertices, procedural::figure_pose(pose), proportions); });
    // rounded to float as `canonform generate` writes it (MeshLab 2020.09 computes in float)
    return {array_out(Eigen::MatrixXd(fig.mesh.V.cast<float>().cast<double>())), array_out(fig.mesh.F)};
}

}  // namespace

void bind_meshes(py::module_& m) {
    m.def("read_mesh", &read_mesh, py::arg("path"), py::kw_only(), py::arg("quality") = false, R"(Reads a mesh file: OFF, PLY (ASCII or binary), OBJ or STL, by extension.

Returns (V, F): V float64 (#V, 3), F int32 (#F, 3) (0-based; (0, 3) for a point
cloud). With quality=True, (V, F, q): q float64 (#V,) the PLY's vertex quality, or
(0,) when the file has none. Raises InputError naming the file and the cause
(missing, a folder, empty, unsupported format, a face index out of range, a
header that claims more than the file holds, malformed data).)");
    m.def("write_mesh", &write_mesh, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("quality") = py::none(),
          R"(Writes a mesh in the format its file name names: .ply (binary, with quality),
.off, .obj, .stl; no extension: PLY. Atomic: a failure leaves no file.

V: float32/float64 (#V, 3); F: integer (#F, 3), or None / (0, 3) for a point
cloud (not STL); quality: None or (#V,) floats, PLY only. Raises InputError for
another extension, an STL point cloud or a face index outside [0, #V).)");
    m.def("conformal_factor", &conformal, py::arg("V"), py::arg("F"), py::arg("normalize") = true, py::kw_only(),
          py::arg("progress") = py::none(), R"(The discrete conformal factor (Pickup et al. 2015, eqs. 7-9).

V: float32/float64 (#V, 3); F: integer (#F, 3), one closed or open manifold
component. Returns phi float64 (#V,): in [0, 1] if normalize (as `canonform
conformal` stores it), else raw with area-weighted mean zero (`--raw`). Raises
InputError on a mesh the library refuses (README, "Bad input"), NumericalError if
the solve fails.)");
    m.def("feature_points", &features, py::arg("V"), py::arg("F"), py::arg("ring") = 2, py::arg("fill") = "none",
          py::arg("seed") = 0, R"(Feature points: vertices that are strict maxima of the conformal factor over
their ring-ring, largest first, up to ceil(sqrt(#V)) (`canonform features`).

fill="random" tops them up to ceil(sqrt(#V)) with seeded random vertices (variant
A). Returns int64 (k,) vertex indices.)");
    m.def("canonical_form", &canonical, py::arg("V"), py::arg("F"), py::arg("method") = "euclidean-N", py::kw_only(),
          py::arg("threads") = 0, py::arg("progress") = py::none(),
          R"(The canonical form of a mesh by any method of the registry (canonical_methods()):
"euclidean-N" (default), "euclidean-A", "geodesic-ls", "geodesic-classical",
"geodesic-fast", "none".

V: float32/float64 (#V, 3); F: integer (#F, 3). **params are the method's
parameters by name (canonical_methods() lists them with defaults and ranges;
e.g. beta=65, tolerance=1e-6, acceleration="none"), checked by the registry: an
unknown name or a value out of range raises InputError naming it. threads: the
method's parallel loops (0: every core). progress: None or
callable(fraction, stage) -> bool|None; returning False raises Cancelled. Ctrl-C
stops the computation (KeyboardInterrupt).

Returns (Y, info): Y float64 (#V, 3), the form in input units, same vertex order
and faces as V; info the dict `canonform canonical --json` prints (vertices,
faces, the method's summary: iterations, stresses, timings...; total_seconds of
this call in place of the tool's read/write/total seconds). The same doubles as
`canonform canonical` on the same mesh with the same parameters.)");
    m.def("canonical_methods", &methods, R"(The registry of canonical-form methods: a list of dicts
{name, family, help, parameters: [{name, default, help, min, max, integer,
choices, zero_means_default}]}, in the order the tool lists them.)");
    m.def("_cpp_call_seconds", &cpp_call_seconds, py::arg("V"), py::arg("F"), py::arg("method") = "euclidean-N",
          "For bench/python_bench.py: seconds of the bare C++ call canonical_form() makes (one thread).");
    m.def("simplify", &simplify, py::arg("V"), py::arg("F"), py::arg("vertices"),
          R"(Quadric edge collapse to about `vertices` vertices (MeshLab's filter, its
defaults; `canonform simplify`). Returns (V float64 (n, 3), F int32 (m, 3)).)");
    m.def("repair_mesh", &repair, py::arg("V"), py::arg("F"),
          R"(The tool's --repair: merges duplicate vertices, removes zero-area and duplicate
faces, keeps the largest component, drops unreferenced vertices. Returns
(V float64, F int32, summary str), the summary saying what changed.)");
    m.def("figure", &figure, py::arg("vertices") = 5000, py::arg("pose") = 0, py::arg("body") = "standard",
          R"(A procedural articulated figure, as `canonform generate OUT --vertices N --pose P
--class BODY` writes it (coordinates rounded to float32). pose 0-5: named poses,
others seeded random ones; body: standard, long-arms, short-legs, long-tail,
stocky, long-neck. Returns (V float64 (#V, 3), F int32 (#F, 3)).)");
}

}  // namespace canonform::python
