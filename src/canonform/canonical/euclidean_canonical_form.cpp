// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/canonical/euclidean_canonical_form.h"

#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_topology.h"

#include "canonform/common/parallel.h"
#include "canonform/numerics/graph.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <sstream>

namespace canonform::canonical {

numerics::StressPairs canonical_form_pairs(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E,
                                           const Eigen::VectorXd& phi, const std::vector<int>& features,
                                           const EuclideanCanonicalFormOptions& options) {
    const bool normalised = options.variant == CanonicalVariant::N;
    const double beta = options.effective_beta();
    const double edge_scale = normalised ? beta / static_cast<double>(E.rows()) : beta;
    numerics::StressPairs pairs;
    const size_t nf = features.size();
    const size_t capacity = static_cast<size_t>(E.rows()) + nf * nf / 2;
    pairs.i.reserve(capacity);  // all four: no doubling of a 1M-vertex mesh's 3M pairs
    pairs.j.reserve(capacity);
    pairs.delta.reserve(capacity);
    pairs.w.reserve(capacity);
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
        const double len = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
        pairs.add(E(e, 0), E(e, 1), len, edge_scale / (len * len));
    }
    double wsum = 0;
    const size_t first_feature_pair = pairs.size();
    for (size_t a = 0; a < nf; ++a) {
        for (size_t b = a + 1; b < nf; ++b) {
            const double w = 0.5 * (phi(features[a]) + phi(features[b]));
            if (!(w > 0)) continue;
            pairs.add(features[a], features[b], options.alpha, w);
            wsum += w;
        }
    }
    if (normalised && wsum > 0)
        for (size_t k = first_feature_pair; k < pairs.size(); ++k) pairs.w[k] /= wsum;
    return pairs;
}

namespace {
/// SMACOF's V and the conformal factor's Laplacian share the mesh's edges; V adds the feature
/// points' clique. So V's factorisation reuses the Laplacian's fill-reducing ordering (which
/// saves the AMD step) with the feature points moved to the end, where their clique is
/// one dense trailing block, as AMD itself would place dense rows. Indices are those of the
/// pinned systems (vertex v > 0 is row v - 1).
std::vector<int> smacof_ordering(const std::vector<int>& laplacian_ordering,
                                 const std::vector<int>& features) {
    if (laplacian_ordering.empty()) return {};
    std::vector<char> is_feature(laplacian_ordering.size(), 0);
    for (const int f : features)
        if (f > 0 && static_cast<size_t>(f) <= is_feature.size()) is_feature[static_cast<size_t>(f - 1)] = 1;
    std::vector<int> order;
    order.reserve(laplacian_ordering.size());
    for (const int k : laplacian_ordering)
        if (!is_feature[static_cast<size_t>(k)]) order.push_back(k);
    for (const int k : laplacian_ordering)
        if (is_feature[static_cast<size_t>(k)]) order.push_back(k);
    return order;
}
}  // namespace

namespace {
/// SMACOF's start for step 4 on (V, E, phi, features) and what it took to make it.
struct SmacofStart {
    Eigen::MatrixXd X;
    int levels = 0, iterations = 0;
};

/// V itself below options.coarse_start_from points; else the form of the coarse problem on the
/// aggregates of the edge graph `adj`, itself started this way, carried back (the header's note).
SmacofStart smacof_start(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E,
                         const numerics::VertexAdjacency& adj, const Eigen::VectorXd& phi,
                         const std::vector<int>& features, const EuclideanCanonicalFormOptions& options) {
    const Eigen::Index n = V.rows();
    SmacofStart start;
    start.X = V;
    if (options.coarse_start_from <= 0 || n < options.coarse_start_from) return start;
    // Aggregates of the edge graph, an edge's strength its weight in step 4 (1 / delta^2 up to beta).
    numerics::WeightedAdjacency graph;
    graph.offsets = adj.offsets;
    graph.neighbors = adj.neighbors;
    graph.strengths.resize(adj.neighbors.size());
    parallel_rows(n, options.threads, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index i = begin; i < end; ++i)
            for (int p = adj.offsets[static_cast<size_t>(i)]; p < adj.offsets[static_cast<size_t>(i) + 1];
                 ++p)
                graph.strengths[static_cast<size_t>(p)] =
                    1.0 / (V.row(i) - V.row(adj.neighbors[static_cast<size_t>(p)])).squaredNorm();
    });
    int nc = 0;
    const std::vector<int> agg = numerics::aggregate_vertices(graph, &nc);
    graph = {};
    if (nc < 2 || nc >= n) return start;
    // The coarse problem: aggregates at their vertices' mean, the edges between them, the feature
    // points' aggregates (the first feature of an aggregate gives it its phi).
    Eigen::MatrixXd Vc = Eigen::MatrixXd::Zero(nc, 3);
    Eigen::VectorXd members = Eigen::VectorXd::Zero(nc);
    for (Eigen::Index i = 0; i < n; ++i) {
        Vc.row(agg[static_cast<size_t>(i)]) += V.row(i);
        members(agg[static_cast<size_t>(i)]) += 1;
    }
    Vc.array().colwise() /= members.array();
    std::vector<std::int64_t> keys;
    keys.reserve(static_cast<size_t>(E.rows()));
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
        const std::int64_t a = agg[static_cast<size_t>(E(e, 0))], b = agg[static_cast<size_t>(E(e, 1))];
        if (a != b) keys.push_back(std::min(a, b) * nc + std::max(a, b));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    Eigen::MatrixXi Ec(static_cast<Eigen::Index>(keys.size()), 2);
    for (size_t k = 0; k < keys.size(); ++k) {
        Ec(static_cast<Eigen::Index>(k), 0) = static_cast<int>(keys[k] / nc);
        Ec(static_cast<Eigen::Index>(k), 1) = static_cast<int>(keys[k] % nc);
        // Two aggregates at one point would give their edge an infinite weight: start from V.
        if (!((Vc.row(Ec(static_cast<Eigen::Index>(k), 0)) - Vc.row(Ec(static_cast<Eigen::Index>(k), 1)))
                  .squaredNorm() > 0))
            return start;
    }
    keys = {};
    Eigen::VectorXd phic = Eigen::VectorXd::Zero(nc);
    std::vector<int> fc;
    std::vector<char> is_feature(static_cast<size_t>(nc), 0);
    for (const int f : features) {
        const int c = agg[static_cast<size_t>(f)];
        if (is_feature[static_cast<size_t>(c)]) continue;
        is_feature[static_cast<size_t>(c)] = 1;
        fc.push_back(c);
        phic(c) = phi(f);
    }
    const numerics::VertexAdjacency adjc = numerics::vertex_adjacency(nc, Ec);
    const SmacofStart inner = smacof_start(Vc, Ec, adjc, phic, fc, options);
    numerics::SmacofSolverOptions solver_opt;
    solver_opt.linear_solver = options.linear_solver;
    solver_opt.threads = options.threads;
    const numerics::SmacofSolver solver(nc, canonical_form_pairs(Vc, Ec, phic, fc, options), solver_opt);
    numerics::SmacofOptions sm_opt = options.smacof;
    sm_opt.progress = nullptr;
    sm_opt.record_history = false;
    const numerics::SmacofResult coarse = solver.solve(inner.X, sm_opt);
    // The coarse displacement (SMACOF centres its result), given to each aggregate's vertices and
    // averaged twice over every vertex and its neighbours.
    const Eigen::MatrixXd Dc = coarse.X - (Vc.rowwise() - Vc.colwise().mean());
    Eigen::MatrixXd D(n, 3), Ds(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) D.row(i) = Dc.row(agg[static_cast<size_t>(i)]);
    for (int pass = 0; pass < 2; ++pass) {
        parallel_rows(n, options.threads, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index c = 0; c < 3; ++c)
                for (Eigen::Index i = begin; i < end; ++i) {
                    double sum = D(i, c);
                    const int b = adj.offsets[static_cast<size_t>(i)],
                              e = adj.offsets[static_cast<size_t>(i) + 1];
                    for (int p = b; p < e; ++p) sum += D(adj.neighbors[static_cast<size_t>(p)], c);
                    Ds(i, c) = sum / (1 + e - b);
                }
        });
        D.swap(Ds);
    }
    start.X = V + D;
    start.levels = inner.levels + 1;
    start.iterations = inner.iterations + coarse.iterations;
    return start;
}
}  // namespace

EuclideanCanonicalFormResult euclidean_canonical_form(const Eigen::MatrixXd& V0, const Eigen::MatrixXi& F,
                                                      const EuclideanCanonicalFormOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!(options.alpha > 0)) throw InputError("alpha must be positive");
    if (options.smacof.max_iterations < 1) throw InputError("the iteration cap must be at least 1");
    if (!(options.smacof.tolerance >= 0)) throw InputError("the tolerance must be non-negative");
    const surface::MeshReport report =
        options.validate ? surface::validate_mesh(V0, F) : surface::MeshReport{};
    report_progress(options.progress, 0.0, "scaling");

    Eigen::RowVector3d centroid;
    double scale = 1;
    const Eigen::MatrixXd V = surface::normalize_scale(V0, &centroid, &scale);

    // Sub-steps report into [0, 0.1] (conformal factor) and [0.1, 1] (SMACOF).
    surface::ConformalFactorOptions cf_opt;
    cf_opt.validate = false;
    cf_opt.boundary = report.boundary;
    cf_opt.linear_solver = options.linear_solver;
    cf_opt.threads = options.threads;
    if (options.progress)
        cf_opt.progress = [&](double f, const char* s) { return options.progress(0.08 * f, s); };
    const auto compute_cf = [&] { return surface::conformal_factor(V, F, cf_opt); };
    // The conformal factor depends on the mesh and the solver only (not on threads).
    const surface::ConformalFactorResult cf =
        options.conformal_factors ? options.conformal_factors(std::string("conformal factor, solver ") +
                                                                  numerics::to_string(options.linear_solver),
                                                              compute_cf)
                                  : compute_cf();
    const auto t1 = std::chrono::steady_clock::now();

    const Eigen::MatrixXi E = report.edge_list.rows() ? report.edge_list : surface::unique_edges(F);
    const numerics::VertexAdjacency adj = numerics::vertex_adjacency(static_cast<int>(V.rows()), E);
    surface::FeaturePointOptions fp_opt = options.features;
    fp_opt.fill =
        options.variant == CanonicalVariant::A ? surface::FeatureFill::Random : surface::FeatureFill::None;
    const surface::FeaturePoints fp = surface::feature_points(adj, cf.normalized, fp_opt);
    report_progress(options.progress, 0.09, "feature points");

    numerics::SmacofSolverOptions solver_opt;
    solver_opt.linear_solver = options.linear_solver;
    solver_opt.threads = options.threads;
    solver_opt.ordering = smacof_ordering(cf.ordering, fp.indices);
    const numerics::SmacofSolver solver(static_cast<int>(V.rows()),
                                        canonical_form_pairs(V, E, cf.normalized, fp.indices, options),
                                        solver_opt);
    report_progress(options.progress, 0.1, "SMACOF: V factorised");

    numerics::SmacofOptions sm_opt = options.smacof;
    const auto t2 = std::chrono::steady_clock::now();
    if (options.progress)
        sm_opt.progress = [&](double f, const char* s) { return options.progress(0.1 + 0.9 * f, s); };
    else
        sm_opt.progress = nullptr;
    report_progress(options.progress, 0.1, "SMACOF: start");
    const SmacofStart start = smacof_start(V, E, adj, cf.normalized, fp.indices, options);
    numerics::SmacofResult sm = solver.solve(start.X, sm_opt);
    const auto t3 = std::chrono::steady_clock::now();

    EuclideanCanonicalFormResult r;
    static_cast<numerics::SmacofStatistics&>(r) = std::move(sm);
    r.mean_relative_edge_change = surface::mean_relative_edge_change(V, sm.X, E);
    r.V = options.restore_scale ? Eigen::MatrixXd((sm.X * scale).rowwise() + centroid) : sm.X;
    r.phi = cf.normalized;
    r.features = fp.indices;
    r.num_maxima = fp.num_maxima;
    r.num_random = fp.num_random;
    r.beta = options.effective_beta();
    r.coarse_levels = start.levels;
    r.coarse_iterations = start.iterations;
    r.linear_solver = solver.linear_solver();
    report_progress(options.progress, 1.0, "done");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.conformal_factor_seconds = std::chrono::duration<double>(t1 - t0).count();
    r.setup_seconds = std::chrono::duration<double>(t2 - t1).count();
    r.smacof_seconds = std::chrono::duration<double>(t3 - t2).count();
    return r;
}

ParameterSet<EuclideanCanonicalFormOptions> euclidean_canonical_form_parameters(
    const EuclideanCanonicalFormOptions& defaults) {
    using O = EuclideanCanonicalFormOptions;
    ParameterSet<O> s(defaults);
    s.add(Parameter::number("alpha", 1e-6, 1e6)
              .label("Alpha")
              .help("target distance of every feature-point pair, in units of the mesh radius (the paper "
                    "uses 10)"),
          &O::alpha);
    s.add(Parameter::number("beta", 0, 1e9)
              .zero_means_default()
              .label("Beta (0 = variant default)")
              .help("edge-length preservation weight; 0: the variant's default, 10 for A and 130 for N"),
          &O::beta);
    s.include(surface::feature_point_parameters(), &O::features, {"ring", "seed"});
    s.include(numerics::smacof_parameters(), &O::smacof);
    s.add(Parameter::choice("solver", numerics::linear_solver_names())
              .label("Linear solver")
              .help("linear solver of SMACOF and the conformal factor: auto (direct below " +
                    std::to_string(numerics::kMultigridFrom) +
                    " vertices, multigrid from there), direct or multigrid")
              .affects_result(false),
          &O::linear_solver);
    return s;
}

CanonicalMethod euclidean_method(CanonicalVariant variant) {
    const bool a = variant == CanonicalVariant::A;
    const ParameterSet<EuclideanCanonicalFormOptions> parameters =
        euclidean_canonical_form_parameters(EuclideanCanonicalFormOptions::of_variant(variant));
    CanonicalMethod m;
    m.name = a ? "euclidean-A" : "euclidean-N";
    m.label = a ? "A" : "N";
    m.family = MethodFamily::Euclidean;
    m.family_default = variant == EuclideanCanonicalFormOptions().variant;
    m.help = a ? "Euclidean canonical form, variant A (extra random feature points, beta 10)"
               : "Euclidean canonical form, variant N (normalised weights, eq. 10, beta 130)";
    m.parameters = parameters.parameters();
    m.run = [parameters](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const MethodSettings& s,
                         const MethodContext& c) {
        EuclideanCanonicalFormOptions o = parameters.read(s);
        o.progress = c.progress;
        o.validate = c.validate;
        o.threads = c.threads;
        o.conformal_factors = c.conformal_factors;
        EuclideanCanonicalFormResult e = euclidean_canonical_form(V, F, o);
        CanonicalForm r;
        r.V = std::move(e.V);
        r.quality = std::move(e.phi);
        r.features = e.features;
        // Grouped: the method, its feature points, the SMACOF run, the result, the timings.
        const std::string variant_name = o.variant == CanonicalVariant::A ? "A" : "N";
        r.summary = {{"method", std::string("euclidean")},
                     {"variant", variant_name},
                     {"alpha", o.alpha},
                     {"beta", e.beta},
                     {"feature_points", static_cast<int>(e.features.size())},
                     {"maxima", e.num_maxima},
                     {"random", e.num_random},
                     {"iterations", e.iterations},
                     {"acceleration", std::string(to_string(o.smacof.acceleration))},
                     {"coarse_levels", e.coarse_levels},
                     {"coarse_iterations", e.coarse_iterations},
                     {"extrapolations", e.extrapolations},
                     {"rejections", e.rejections},
                     {"converged", e.converged},
                     {"initial_stress", e.initial_stress},
                     {"final_stress", e.final_stress},
                     {"solver", std::string(to_string(e.linear_solver))},
                     {"mean_relative_edge_change", e.mean_relative_edge_change},
                     {"seconds", e.seconds},
                     {"conformal_factor_seconds", e.conformal_factor_seconds},
                     {"setup_seconds", e.setup_seconds},
                     {"smacof_seconds", e.smacof_seconds}};
        std::ostringstream d;
        d << "variant " << variant_name << ", alpha " << o.alpha << ", beta " << e.beta << ": " << V.rows()
          << " vertices, " << e.features.size() << " feature points (" << e.num_maxima << " maxima, "
          << e.num_random << " random), " << e.iterations << " SMACOF iterations ("
          << to_string(o.smacof.acceleration) << ")" << (e.converged ? "" : " (iteration cap reached)");
        if (e.coarse_levels > 0)
            d << " from a coarse start (" << e.coarse_levels
              << (e.coarse_levels == 1 ? " level, " : " levels, ") << e.coarse_iterations << " iterations)";
        d << ", stress " << e.initial_stress << " -> " << e.final_stress
          << ", mean relative edge-length change " << e.mean_relative_edge_change << ", " << e.seconds
          << " s";
        r.description = d.str();
        return r;
    };
    return m;
}

}  // namespace canonform::canonical
