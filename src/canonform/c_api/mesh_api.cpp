// SPDX-License-Identifier: GPL-3.0-or-later
// canonform C API (canonform.h): meshes - files, repair, simplification, procedural figures - and
// the canonical forms, conformal factor and feature points.
#include "canonform/c_api/c_api_support.h"
#include "canonform/c_api/json_text.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"
#ifdef CANONFORM_C_API_RETRIEVAL
#include "canonform/surface/simplify.h"
#endif

#include <chrono>
#include <cstring>
#include <limits>
#include <string>
#include <variant>

using namespace canonform;
using namespace canonform::c_api;

namespace {

/// Checks a value against a parameter of the registry (its range is defined there once).
void check_as(const char* method, const char* parameter, const std::string& value) {
    const Parameter* p = canonical::canonical_method(method).parameter(parameter);
    if (p) p->check(value);
}

void mesh_out(const Mesh& m, canonform_array** V_out, canonform_array** F_out) {
    ArrayPtr v = array_out(m.V);
    ArrayPtr f = array_out(m.F);
    *V_out = v.release();
    *F_out = f.release();
}

}  // namespace

extern "C" {

int canonform_read_mesh(const char* path, canonform_array** V, canonform_array** F,
                        canonform_array** quality) {
    clear_outputs(V, F, quality);
    return guarded([&] {
        require_out(V, "V");
        require_out(F, "F");
        const io::MeshFile f = io::read_mesh_file(text_in(path, "path"));
        ArrayPtr v = array_out(f.mesh.V), fa = array_out(f.mesh.F);
        ArrayPtr q(nullptr);
        if (quality) q = vector_out(f.quality);
        *V = v.release();
        *F = fa.release();
        if (quality) *quality = q.release();
    });
}

int canonform_write_mesh(const char* path, const double* V, int64_t nv, const int32_t* F, int64_t nf,
                         const double* quality) {
    return guarded([&] {
        const std::string p = text_in(path, "path");
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        Eigen::VectorXd q;
        if (quality && nv > 0) q = Eigen::Map<const Eigen::VectorXd>(quality, nv);
        io::write_mesh(p, v, f, q);
    });
}

int canonform_repair_mesh(const double* V, int64_t nv, const int32_t* F, int64_t nf, canonform_array** V_out,
                          canonform_array** F_out, char** summary) {
    clear_outputs(V_out, F_out, summary);
    return guarded([&] {
        require_out(V_out, "V_out");
        require_out(F_out, "F_out");
        const surface::MeshRepair r = surface::repair_mesh(vertices_in(V, nv), faces_in(F, nf));
        char* s = summary ? text_out(r.summary()) : nullptr;
        try {
            mesh_out(r.mesh, V_out, F_out);
        } catch (...) {
            canonform_free(s);
            throw;
        }
        if (summary) *summary = s;
    });
}

int canonform_simplify(const double* V, int64_t nv, const int32_t* F, int64_t nf, int64_t vertices,
                       canonform_array** V_out, canonform_array** F_out) {
    clear_outputs(V_out, F_out);
    return guarded([&] {
        require_out(V_out, "V_out");
        require_out(F_out, "F_out");
#ifdef CANONFORM_C_API_RETRIEVAL
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        if (vertices < std::numeric_limits<int>::min() || vertices > std::numeric_limits<int>::max())
            check_range("vertices", vertices, 4, 100000000);
        surface::validate_mesh(v, f);
        mesh_out(surface::simplify_mesh(Mesh{v, f}, static_cast<int>(vertices)), V_out, F_out);
#else
        (void)V, (void)nv, (void)F, (void)nf, (void)vertices;
        throw Unsupported(
            "simplify: this build of canonform has no retrieval area (configure with "
            "CANONFORM_RETRIEVAL=ON)");
#endif
    });
}

int canonform_figure(int64_t vertices, int64_t pose, const char* body, canonform_array** V_out,
                     canonform_array** F_out) {
    clear_outputs(V_out, F_out);
    return guarded([&] {
        require_out(V_out, "V_out");
        require_out(F_out, "F_out");
        check_range("vertices", vertices, 500, 2000000);
        if (pose < 0) throw InputError("pose must be 0 or more, got " + std::to_string(pose));
        if (pose > std::numeric_limits<int>::max())
            check_range("pose", pose, 0, std::numeric_limits<int>::max());
        procedural::FigureProportions proportions;
        try {
            proportions = procedural::figure_class(body ? body : "standard");
        } catch (const std::invalid_argument& e) {
            throw InputError(e.what());
        }
        const procedural::Figure fig = procedural::make_figure(
            static_cast<int>(vertices), procedural::figure_pose(static_cast<int>(pose)), proportions);
        // rounded to float as `canonform generate` writes it (MeshLab 2020.09 computes in float)
        mesh_out(Mesh{fig.mesh.V.cast<float>().cast<double>(), fig.mesh.F}, V_out, F_out);
    });
}

int canonform_methods_json(char** json) {
    clear_outputs(json);
    return guarded([&] {
        require_out(json, "json");
        JsonWriter w;
        w.begin_array();
        for (const canonical::CanonicalMethod* method : canonical::canonical_methods()) {
            const canonical::CanonicalMethod& m = *method;
            const char* family = m.family == canonical::MethodFamily::Euclidean  ? "euclidean"
                                 : m.family == canonical::MethodFamily::Geodesic ? "geodesic"
                                                                                 : "none";
            w.begin_object().key("name").value(m.name).key("family").value(family).key("help").value(m.help);
            w.key("parameters").begin_array();
            for (const Parameter& p : m.parameters)
                w.begin_object()
                    .key("name")
                    .value(p.name())
                    .key("default")
                    .value(p.default_value())
                    .key("help")
                    .value(p.help())
                    .key("min")
                    .value(p.min())
                    .key("max")
                    .value(p.max())
                    .key("integer")
                    .value(p.type() == ParameterType::Int)
                    .key("choices")
                    .value(p.choices())
                    .key("zero_means_default")
                    .value(p.zero_means_default())
                    .end_object();
            w.end_array().end_object();
        }
        w.end_array();
        *json = text_out(w.text());
    });
}

int canonform_canonical_form(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                             const char* method_name, const char* const* keys, const char* const* values,
                             int64_t nparams, int threads, canonform_progress_fn progress, void* user,
                             double* Y, canonform_array** quality, char** info) {
    clear_outputs(quality, info);
    return guarded([&] {
        if (nv > 0) require_out(Y, "Y");  // (an empty mesh is refused by the validation below)
        canonical::MethodSpec spec;
        spec.name = method_name ? method_name : "euclidean-N";
        const canonical::CanonicalMethod& method =
            canonical::canonical_method(spec.name);  // InputError listing the names
        if (nparams < 0 || (nparams > 0 && (!keys || !values)))
            throw InputError("parameters: " + std::to_string(nparams) +
                             " given without their names and values");
        for (int64_t k = 0; k < nparams; ++k)
            spec.given.emplace_back(text_in(keys[k], "a parameter name"),
                                    text_in(values[k], "a parameter value"));
        const canonical::MethodSettings settings =
            spec.settings();  // every name and value checked by the registry
        check_range("threads", threads, 0, 1024);
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        canonical::MethodContext context;
        context.threads = threads;
        context.progress = progress_in(progress, user);
        context.validate = false;  // validated just before, as the tool does
        surface::validate_mesh(v, f);
        const canonical::CanonicalForm r = method.run(v, f, settings, context);
        if (!r.V.allFinite())
            throw NumericalError("method " + method.name + " gave a form with NaN or infinite coordinates");
        // The tool's --json summary: the mesh, then the method's summary in its order.
        char* text = nullptr;
        if (info) {
            JsonWriter j;
            j.begin_object().key("vertices").integer(v.rows()).key("faces").integer(f.rows());
            for (const auto& [key, value] : r.summary)
                std::visit([&, k = key](const auto& x) { j.key(k).value(x); }, value);
            text = text_out(j.end_object().text());
        }
        ArrayPtr q(nullptr);
        try {
            if (quality) q = vector_out(r.quality);
        } catch (...) {
            canonform_free(text);
            throw;
        }
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(Y, r.V.rows(), 3) = r.V;
        if (quality) *quality = q.release();
        if (info) *info = text;
    });
}

int canonform_conformal_factor(const double* V, int64_t nv, const int32_t* F, int64_t nf, int normalize,
                               canonform_progress_fn progress, void* user, double* phi) {
    return guarded([&] {
        if (nv > 0) require_out(phi, "phi");
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        surface::ConformalFactorOptions o;
        o.progress = progress_in(progress, user);
        const surface::ConformalFactorResult r = surface::conformal_factor(v, f, o);
        const Eigen::VectorXd& out = normalize ? r.normalized : r.raw;
        if (out.size()) std::memcpy(phi, out.data(), sizeof(double) * static_cast<size_t>(out.size()));
    });
}

int canonform_feature_points(const double* V, int64_t nv, const int32_t* F, int64_t nf, int64_t ring,
                             const char* fill, int64_t seed, canonform_progress_fn progress, void* user,
                             canonform_array** indices) {
    clear_outputs(indices);
    return guarded([&] {
        require_out(indices, "indices");
        check_as("euclidean-N", "ring", std::to_string(ring));
        check_as("euclidean-A", "seed", std::to_string(seed));
        surface::FeaturePointOptions o;
        o.ring = static_cast<int>(ring);
        const std::string how = fill ? fill : "none";
        if (how == "none")
            o.fill = surface::FeatureFill::None;
        else if (how == "random")
            o.fill = surface::FeatureFill::Random;
        else
            throw InputError("fill must be 'none' or 'random', got '" + how + "'");
        o.seed = static_cast<std::uint64_t>(seed);
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        surface::ConformalFactorOptions co;
        co.progress = progress_in(progress, user);
        const surface::FeaturePoints fp =
            surface::feature_points(f, surface::conformal_factor(v, f, co).normalized, o);
        *indices = indices_out(fp.indices).release();
    });
}

int canonform_time_canonical_form(const double* V, int64_t nv, const int32_t* F, int64_t nf,
                                  const char* method_name, double* seconds) {
    return guarded([&] {
        require_out(seconds, "seconds");
        const canonical::CanonicalMethod& method =
            canonical::canonical_method(method_name ? method_name : "euclidean-N");
        const canonical::MethodSettings settings = method.settings();
        const Eigen::MatrixXd v = vertices_in(V, nv);
        const Eigen::MatrixXi f = faces_in(F, nf);
        canonical::MethodContext context;
        context.threads = 1;
        const auto t0 = std::chrono::steady_clock::now();
        const canonical::CanonicalForm r = method.run(v, f, settings, context);
        *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (r.V.rows() != v.rows()) throw NumericalError("unexpected form size");
    });
}

}  // extern "C"
