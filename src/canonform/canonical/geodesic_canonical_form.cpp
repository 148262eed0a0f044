// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/geodesic_canonical_form.h"

#include "canonform/common/parallel.h"

#include "canonform/numerics/mds.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/geodesic_distances.h"
#include "canonform/surface/mesh_topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace canonform::canonical {

namespace {

/// Threads that can run at once: the request, at most every hardware thread.
int effective_threads(int threads) {
    return std::min(thread_count(threads), thread_count());
}

}  // namespace

std::string GeodesicCost::describe() const {
    char buf[96];
    std::snprintf(buf, sizeof buf, "about %.2f GiB and %.0f s", bytes / (1024.0 * 1024.0 * 1024.0), seconds);
    return buf;
}

GeodesicCost estimate_geodesic_canonical_form(long n, numerics::MdsMethod method, int threads) {
    // Memory: the n x n distance matrix and the solver's own n x n work matrix (SMACOF and
    // classical MDS square or copy it), plus the fast-marching buffers.
    // Time: fast marching 2.0e-8 n^2 log2(n) s on one core (geodesic_distances.cpp), divided by
    // the threads at 80% efficiency; MDS per n^2 pair: SMACOF ~100 Guttman steps of ~6 ns,
    // classical ~40 subspace steps of ~2 ns, landmark MDS negligible. Measured on a 2-core
    // 2026 x86-64 machine at 1k-4k vertices; the estimate is meant to be within a factor of 2.
    const double nn = static_cast<double>(n) * static_cast<double>(n);
    const int t = effective_threads(threads);
    const double speedup = 1.0 + 0.8 * (t - 1);
    GeodesicCost c;
    c.bytes = static_cast<double>(surface::all_pairs_geodesic_bytes(n)) +
              (method == numerics::MdsMethod::Landmark ? 0.0 : 8.0 * nn) + 64.0 * static_cast<double>(n);
    double mds = 0;
    if (method == numerics::MdsMethod::LeastSquares) mds = 100 * 6e-9 * nn;
    if (method == numerics::MdsMethod::Classical) mds = 40 * 2e-9 * nn;
    c.seconds = (surface::all_pairs_geodesic_seconds_estimate(n) + mds) / speedup;
    return c;
}

GeodesicCanonicalFormResult geodesic_canonical_form(const Eigen::MatrixXd& V0, const Eigen::MatrixXi& F,
                                                    const GeodesicCanonicalFormOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const surface::MeshReport report = surface::validate_mesh(V0, F);
    GeodesicCanonicalFormResult r;
    r.estimate = estimate_geodesic_canonical_form(V0.rows(), options.method, options.threads);
    const double gib = r.estimate.bytes / (1024.0 * 1024.0 * 1024.0);
    if (gib > options.max_memory_gib || r.estimate.seconds > options.max_seconds) {
        std::ostringstream m;
        m << "a geodesic canonical form of " << V0.rows() << " vertices needs " << r.estimate.describe()
          << " (all-pairs geodesic distances grow like N^2), over the limits of " << options.max_memory_gib
          << " GiB and " << options.max_seconds
          << " s; raise max_memory_gib / max_seconds, simplify the mesh first, or use the Euclidean "
             "canonical "
             "form";
        throw InputError(m.str());
    }
    Eigen::RowVector3d centroid;
    double scale = 1;
    const Eigen::MatrixXd V = surface::normalize_scale(V0, &centroid, &scale);

    // Step 2: geodesics, reported in [0, 0.7] of the progress.
    surface::GeodesicOptions g;
    g.threads = options.threads;
    if (options.progress) g.progress = [&](double f, const char* s) { return options.progress(0.7 * f, s); };
    const auto tg = std::chrono::steady_clock::now();
    const Eigen::MatrixXd D = surface::all_pairs_geodesic_distances(V, F, g);
    r.geodesic_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tg).count();
    if (!D.allFinite()) throw NumericalError("geodesic distances: some vertices were not reached");

    // Step 3: MDS in [0.7, 1]. Least squares starts from classical MDS (see the header).
    numerics::MdsOptions mo = options.mds;
    mo.dim = 3;
    mo.threads = options.threads;
    mo.check_input = false;  // symmetric with zero diagonal by construction
    mo.progress = nullptr;
    if (options.progress)
        mo.progress = [&](double f, const char* s) { return options.progress(0.7 + 0.3 * f, s); };
    const auto tm = std::chrono::steady_clock::now();
    numerics::MdsResult m = numerics::mds(D, options.method, mo);
    r.mds_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tm).count();
    if (m.X.cols() != 3 || !m.X.allFinite()) throw NumericalError("MDS returned a non-finite configuration");

    static_cast<numerics::SmacofStatistics&>(r) = std::move(m);  // X stays in m
    r.mean_relative_edge_change = surface::mean_relative_edge_change(V, m.X, report.edge_list);
    r.V = options.restore_scale ? Eigen::MatrixXd((m.X * scale).rowwise() + centroid) : m.X;
    report_progress(options.progress, 1.0, "done");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

ParameterSet<GeodesicCanonicalFormOptions> geodesic_canonical_form_parameters(
    const GeodesicCanonicalFormOptions& defaults) {
    using O = GeodesicCanonicalFormOptions;
    ParameterSet<O> s(defaults);
    s.include(numerics::mds_parameters(), &O::mds);
    s.add(Parameter::number("max_memory_gib", 0, 1e6)
              .label("Memory limit (GiB)")
              .help("refuse meshes whose estimated memory (an N x N distance matrix) exceeds this (GiB)")
              .affects_result(false),
          &O::max_memory_gib);
    s.add(Parameter::number("max_seconds", 0, 1e9)
              .label("Time limit (s)")
              .help("refuse meshes whose estimated computing time exceeds this (s)")
              .affects_result(false),
          &O::max_seconds);
    return s;
}

CanonicalMethod geodesic_method(numerics::MdsMethod mds) {
    GeodesicCanonicalFormOptions defaults;
    defaults.method = mds;
    const ParameterSet<GeodesicCanonicalFormOptions> parameters =
        geodesic_canonical_form_parameters(defaults);
    CanonicalMethod m;
    m.family = MethodFamily::Geodesic;
    m.family_default = mds == GeodesicCanonicalFormOptions().method;
    switch (mds) {
        case numerics::MdsMethod::LeastSquares:
            m.name = "geodesic-ls";
            m.label = "least squares";
            m.help = "geodesic canonical form, least-squares MDS (SMACOF on all pairs; the paper's LS)";
            break;
        case numerics::MdsMethod::Classical:
            m.name = "geodesic-classical";
            m.label = "classical";
            m.help = "geodesic canonical form, classical MDS (the paper's C)";
            break;
        case numerics::MdsMethod::Landmark:
            m.name = "geodesic-fast";
            m.label = "fast";
            m.help = "geodesic canonical form, fast (landmark) MDS (the paper's F)";
            break;
    }
    m.parameters = parameters.parameters();
    // Only least squares runs SMACOF: the others accept its acceleration, which changes nothing.
    if (mds != numerics::MdsMethod::LeastSquares)
        for (Parameter& p : m.parameters)
            if (p.name() == "acceleration") p.affects_result(false);
    const std::string name = m.name;
    m.run = [parameters, mds, name](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                    const MethodSettings& s, const MethodContext& c) {
        GeodesicCanonicalFormOptions o = parameters.read(s);
        o.threads = c.threads;
        o.progress = c.progress;
        GeodesicCanonicalFormResult g = geodesic_canonical_form(V, F, o);
        CanonicalForm r;
        r.V = std::move(g.V);
        const std::string acceleration =
            mds == numerics::MdsMethod::LeastSquares ? to_string(o.mds.smacof.acceleration) : "none";
        r.summary = {{"method", name},
                     {"iterations", g.iterations},
                     {"acceleration", acceleration},
                     {"initial_stress", g.initial_stress},
                     {"final_stress", g.final_stress},
                     {"mean_relative_edge_change", g.mean_relative_edge_change},
                     {"geodesic_seconds", g.geodesic_seconds},
                     {"mds_seconds", g.mds_seconds},
                     {"seconds", g.seconds},
                     {"estimated_seconds", g.estimate.seconds},
                     {"estimated_bytes", g.estimate.bytes}};
        std::ostringstream d;
        d << name << ": " << V.rows() << " vertices (estimated " << g.estimate.describe() << "), geodesics "
          << g.geodesic_seconds << " s, MDS " << g.mds_seconds << " s (" << g.iterations
          << " iterations, stress " << g.initial_stress << " -> " << g.final_stress
          << "), mean relative edge-length change " << g.mean_relative_edge_change << ", " << g.seconds
          << " s";
        r.description = d.str();
        return r;
    };
    return m;
}

}  // namespace canonform::canonical
