// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/experiment.h"

#include "canonform/common/elapsed.h"
#include "canonform/common/parallel.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/numerics/portable_math.h"
#include "canonform/numerics/rigid_alignment.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/surface/simplify.h"
#include "canonform/views/view_directions.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <unordered_set>

namespace canonform::retrieval {

namespace {

/// Seeded vertex noise: every coordinate moves by N(0, (sigma * mean edge length)^2).
void add_noise(Mesh& m, double sigma, std::uint64_t seed) {
    const Eigen::MatrixXi E = surface::unique_edges(m.F);
    double mean = 0;
    for (Eigen::Index e = 0; e < E.rows(); ++e) mean += (m.V.row(E(e, 0)) - m.V.row(E(e, 1))).norm();
    mean /= static_cast<double>(std::max<Eigen::Index>(1, E.rows()));
    std::mt19937_64 rng(seed);
    numerics::StandardNormalDraws g;  // the same noise with every C library (portable_math.h)
    for (Eigen::Index i = 0; i < m.V.rows(); ++i)
        for (int c = 0; c < 3; ++c) m.V(i, c) += sigma * mean * g(rng);
}

/// Ground-truth correspondences of a model (empty if the collection has none for it).
std::vector<int> read_vts(const std::string& dataset, const std::string& name) {
    std::ifstream in(io::fs_path(dataset + "/corres/" + name + ".vts"));
    std::vector<int> v;
    for (int x; in >> x;) v.push_back(x - 1);
    return v;
}

void log_line(const ExperimentOptions& o, const std::string& line) {
    if (o.log) o.log(line);
}

/// A method's measures: `js` (its identity) completed with the micro and macro measures or why
/// there are none, then `pose` fields, written to DIR/metrics.json; the precision-recall curve to
/// DIR/pr.csv; one log line. Timings stay out of metrics.json (equal for equal inputs).
void write_measures(const ExperimentOptions& o, const std::string& dir, const std::string& label,
                    nlohmann::ordered_json js, const nlohmann::ordered_json& pose, const MethodOutcome& out) {
    js["meshes"] = out.meshes;
    js["failed"] = out.failed;
    if (out.no_measures.empty()) {
        js["micro"] = to_json(out.evaluation.micro);
        js["macro"] = to_json(out.evaluation.macro);
    } else {
        js["micro"] = nullptr;
        js["macro"] = nullptr;
        js["no_measures"] = out.no_measures;
    }
    for (const auto& [key, value] : pose.items()) js[key] = value;
    io::write_file_atomic(dir + "/metrics.json",
                          js.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
    if (!out.no_measures.empty() || !out.evaluation.recall.empty()) {  // measures without a matrix: no curve
        std::ostringstream pr;
        pr << "recall,precision\n";
        for (size_t k = 0; k < out.evaluation.recall.size(); ++k)
            pr << out.evaluation.recall[k] << "," << out.evaluation.precision[k] << "\n";
        io::write_file_atomic(dir + "/pr.csv", pr.str());
    }
    const Measures& e = out.evaluation.micro;
    char line[300];
    std::snprintf(line, sizeof line, "[%s] NN %.3f, 1-tier %.3f, 2-tier %.3f, E %.3f, DCG %.3f",
                  label.c_str(), e.nn, e.first_tier, e.second_tier, e.e_measure, e.dcg);
    log_line(o, out.no_measures.empty() ? line : "[" + label + "] no measures: " + out.no_measures);
}

}  // namespace

std::vector<Model> read_collection(const std::string& dataset, const std::string& labels, int threads) {
    std::vector<Model> models;
    std::map<std::string, std::string> names;  // name -> path
    for (const io::LabelRow& row : io::read_labels(labels)) {
        if (row.path.empty()) continue;
        Model m;
        m.path = dataset + "/" + row.path;
        m.label = row.label;
        m.name = io::stem(m.path);
        const auto [it, fresh] = names.emplace(m.name, m.path);
        if (!fresh)
            throw InputError("'" + labels + "': two models are named '" + m.name + "' ('" + it->second +
                             "' and '" + m.path +
                             "'): their forms and descriptors would overwrite each other");
        models.push_back(m);
    }
    // The files' hashes (the cache keys' content part), in parallel: reading 600 meshes of 10k
    // vertices and hashing them byte by byte took one core about a second.
    ParallelOptions par;
    par.threads = threads;
    parallel_for(
        static_cast<std::ptrdiff_t>(models.size()),
        [&](std::ptrdiff_t k, int) {
            Model& m = models[static_cast<size_t>(k)];
            try {
                m.hash = io::fnv1a(io::read_file(m.path));
            } catch (const InputError& e) {
                m.error = e.what();  // listed as a failure of every method, not a stop
            }
        },
        par);
    return models;
}

// One slot per model: the settings' key and what the Euclidean form reads of the conformal factor
// (normalized, ordering). A slot is only touched by the task of its model (methods run one after
// another), so the slots need no lock; the byte count is shared.
struct Experiment::ConformalFactors {
    static constexpr std::size_t kBudget = std::size_t(256) << 20;
    std::vector<std::string> key;
    std::vector<surface::ConformalFactorResult> kept;
    std::atomic<std::size_t> bytes{0};
    explicit ConformalFactors(std::size_t models) : key(models), kept(models) {}

    surface::ConformalFactorResult get(std::size_t model, const std::string& k,
                                       const std::function<surface::ConformalFactorResult()>& compute) {
        if (!key[model].empty() && key[model] == k) return kept[model];
        surface::ConformalFactorResult r = compute();
        if (!key[model].empty()) return r;  // the slot keeps the first settings' factor
        const std::size_t size =
            sizeof(double) * static_cast<std::size_t>(r.normalized.size()) + sizeof(int) * r.ordering.size();
        std::size_t used = bytes.load();
        while (used + size <= kBudget && !bytes.compare_exchange_weak(used, used + size)) {
        }
        if (used + size <= kBudget) {
            kept[model].normalized = r.normalized;
            kept[model].ordering = r.ordering;
            key[model] = k;
        }
        return r;
    }
};

Experiment::Experiment(ExperimentOptions options)
    : Experiment(options, options.methods.empty()
                              ? std::vector<Model>{}
                              : read_collection(options.dataset, options.labels, options.threads)) {}

Experiment::Experiment(ExperimentOptions options, std::vector<Model> models)
    : options_(std::move(options)), models_(std::move(models)) {
    const ExperimentOptions& o = options_;
    for (const FusedSpec& f : options_.fused)
        for (const std::string& member : f.members) {
            const canonical::MethodSpec m = canonical::parse_method_spec(member);
            bool listed = false;
            for (const canonical::MethodSpec& x : options_.methods)
                listed = listed || x.folder() == m.folder();
            if (!listed) options_.methods.push_back(m);
        }
    if (o.methods.empty()) throw InputError("name at least one --method");
    for (size_t k = 0; k < o.methods.size(); ++k)
        for (size_t j = 0; j < k; ++j)
            if (o.methods[j].folder() == o.methods[k].folder())
                throw InputError("method '" + o.methods[k].to_string() + "' is named twice");
    if (models_.size() < 3)
        throw InputError("'" + o.labels + "': the collection needs at least three meshes");
    int euclidean = 0;
    for (const canonical::MethodSpec& m : o.methods)
        euclidean += m.method().family == canonical::MethodFamily::Euclidean;
    if (euclidean >= 2) conformal_factors_ = std::make_shared<ConformalFactors>(models_.size());
    // The measures average over the classes of three or more models (psbTable's rule); say before
    // any work when no class qualifies: the distances are still computed and written.
    std::map<std::string, int> sizes;
    for (const Model& m : models_) ++sizes[m.label];
    std::string small;
    int measurable = 0;
    for (const auto& [label, count] : sizes) {
        if (count > 2)
            ++measurable;
        else
            small += (small.empty() ? "" : ", ") + label + " (" + std::to_string(count) + ")";
    }
    if (measurable == 0)
        log_line(
            o,
            "note: no class of '" + o.labels + "' has more than two models (" + small +
                "): the retrieval measures need three; the distances will be written, the measures left out");
    else if (!small.empty())
        log_line(o, "note: classes with two models or fewer are left out of the measures: " + small);
    io::make_directories(o.out + "/cache");
    // The collection as this run read it (name, class, mesh), for `canonform grid`.
    std::ostringstream c;
    c << "name,class,path\n";
    for (const Model& m : models_) c << m.name << "," << m.label << "," << m.path << "\n";
    io::write_file_atomic(o.out + "/collection.csv", c.str());
}

std::string Experiment::cache_entry(const canonical::MethodSpec& method, std::size_t k) const {
    const ExperimentOptions& o = options_;
    std::ostringstream params;
    // The form and its views depend on the seed only through the noise (the codebook's seed is
    // in the codebook's key): without noise, runs with other seeds share these entries.
    params << method.cache_key() << "|simplify=" << o.simplify << "|noise=" << o.noise
           << (o.noise > 0 ? "|seed=" + std::to_string(o.seed) : std::string()) << "|views=v1"
           << (o.repair ? "|repair" : "")
           << (o.views.sift.backend != views::SiftBackend::OpenCV
                   ? "|sift=" + views::sift_backend_name(o.views.sift.backend)
                   : std::string());
    return o.out + "/cache/" + io::hex(io::fnv1a(params.str(), models_[k].hash));
}

MeshFeatures Experiment::mesh_features(const canonical::MethodSpec& method, std::size_t k) const {
    const ExperimentOptions& o = options_;
    const Model& model = models_[k];
    MeshFeatures r;
    const std::string key = cache_entry(method, k);
    const std::string cached_descriptor = key + ".cfvd", cached_form = key + ".ply";
    const std::string form = o.out + "/" + method.folder() + "/forms/" + model.name + ".ply";
    if (!model.error.empty()) {
        r.error = model.error;
        return r;
    }
    // A cache hit also restores the form (forms/ may hold one of other parameters, or none, and
    // the pose consistency and the grid read it); an entry without its form is recomputed, and
    // so is one that cannot be read (a corrupt or truncated file).
    if (io::is_file(cached_descriptor) && io::is_file(cached_form)) {
        try {
            const std::string form_bytes = io::read_file(cached_form);
            const Mesh cached = io::parse_mesh(form_bytes, io::MeshFormat::Ply, cached_form).mesh;
            if (!cached.V.allFinite()) throw InputError("'" + cached_form + "': NaN or infinite coordinates");
            r.features = views::read_descriptor(cached_descriptor).raw;
            io::write_file_atomic(form, form_bytes);
            r.ok = r.cached = true;
            return r;
        } catch (const std::exception& e) {
            r.features.clear();
            r.note = std::string("corrupt cache entry recomputed (") + e.what() + ")";
        }
    }
    try {
        Mesh m = io::read_mesh(model.path);
        if (o.repair) {
            const surface::MeshRepair fix = surface::repair_mesh(m.V, m.F);
            if (fix.changed()) r.note += (r.note.empty() ? "" : "; ") + fix.summary();
            m = fix.mesh;
        }
        if (o.simplify > 0 && m.V.rows() > o.simplify) {
            m = surface::simplify_mesh(m, o.simplify);
        } else if (o.simplify > 0) {  // said, not silent: the mesh is already at most that size
            r.note += (r.note.empty() ? "" : "; ") + std::string("not simplified: ") +
                      std::to_string(m.V.rows()) + " vertices, at most the --simplify " +
                      std::to_string(o.simplify);
        }
        if (o.noise > 0) add_noise(m, o.noise, o.seed ^ model.hash);
        canonical::MethodContext context;
        context.threads = 1;  // the meshes run in parallel
        if (conformal_factors_)
            context.conformal_factors = [this, k](const std::string& settings, const auto& compute) {
                return conformal_factors_->get(k, settings, compute);
            };
        const Eigen::MatrixXd X = method.method().run(m.V, m.F, method.settings(), context).V;
        if (!X.allFinite()) throw NumericalError("the method gave a form with NaN or infinite coordinates");
        io::write_ply(form, X, m.F);
        io::write_file_atomic(cached_form, io::read_file(form));
        views::ViewDescriptorOptions vo = o.views;
        vo.keep_images = false;  // the features are what a run keeps
        const views::ViewSet vs = views::compute_views(X, m.F, vo);
        views::write_descriptor(cached_descriptor, views::make_descriptor(vs.features, nullptr, model.path));
        r.features = vs.features;
        r.ok = true;
    } catch (const std::exception& e) {
        r.error = e.what();
    }
    return r;
}

std::vector<MeshFeatures> Experiment::features(const canonical::MethodSpec& method) const {
    io::make_directories(options_.out + "/" + method.folder() + "/forms");
    std::vector<MeshFeatures> results(models_.size());
    ParallelOptions par;
    par.threads = options_.threads;
    par.stage = "meshes";
    if (options_.progress) par.progress = options_.progress(method.folder());
    parallel_for(
        static_cast<std::ptrdiff_t>(models_.size()),
        [&](std::ptrdiff_t k, int) {
            results[static_cast<size_t>(k)] = mesh_features(method, static_cast<size_t>(k));
        },
        par);
    return results;
}

views::CodebookOptions Experiment::codebook_options() const {
    views::CodebookOptions co = options_.codebook_training;
    co.words = options_.words;
    co.seed = options_.seed;
    return co;
}

views::Codebook Experiment::codebook(const canonical::MethodSpec& method,
                                     const std::vector<MeshFeatures>& features,
                                     const std::vector<std::size_t>& good) const {
    const ExperimentOptions& o = options_;
    if (!o.codebook.empty()) return views::Codebook::load(o.codebook);
    const views::CodebookOptions co = codebook_options();
    std::string key =
        method.cache_key() + "|words=" + std::to_string(o.words) + "|seed=" + std::to_string(o.seed);
    if (co.method != views::CodebookOptions::Method::Lloyd || co.sample != 0 || co.kmeans_iterations != 10)
        key += "|" + views::codebook_method_name(co.method) + "|sample=" + std::to_string(co.sample) +
               "|iterations=" + std::to_string(co.kmeans_iterations);  // (the old key is Lloyd's on all)
    if (o.views.sift.backend != views::SiftBackend::OpenCV)
        key += "|sift=" + views::sift_backend_name(o.views.sift.backend);
    // The features it is trained on also depend on these (they were missing from the key, so a
    // run with --noise or --simplify reused the codebook of the plain run in the same folder).
    if (o.simplify > 0) key += "|simplify=" + std::to_string(o.simplify);
    if (o.noise > 0) key += "|noise=" + std::to_string(o.noise);
    if (o.repair) key += "|repair";
    std::uint64_t h = io::fnv1a(key);
    std::vector<std::size_t> counts;
    std::int64_t total = 0;
    for (size_t k : good) {
        h = io::fnv1a(io::hex(models_[k].hash), h);
        counts.push_back(views::feature_rows(features[k].features));
        total += static_cast<std::int64_t>(counts.back());
    }
    const std::string path = o.out + "/cache/codebook_" + io::hex(h) + ".bin";
    if (io::is_file(path)) return views::Codebook::load(path);
    // Trained on the sample alone (the same words as on the whole stack: codebook.h).
    const views::SiftDescriptors sample =
        views::stacked_rows(counts, views::Codebook::training_rows(total, co),
                            [&](std::size_t g) -> const std::vector<views::SiftDescriptors>& {
                                return features[good[g]].features;
                            });
    views::Codebook cb = views::Codebook::train_on_rows(sample, total, co);
    cb.save(path);
    return cb;
}

MethodOutcome Experiment::run_method(const canonical::MethodSpec& spec) const {
    const ExperimentOptions& o = options_;
    MethodOutcome out;
    out.spec = spec;
    const std::string method = spec.folder();
    const std::string dir = o.out + "/" + method;
    out.folder = dir;
    io::make_directories(dir + "/descriptors");

    // 1. Per mesh, in parallel: canonical form and the SIFT features of its views (cached).
    auto t0 = SteadyClock::now();
    const std::vector<MeshFeatures> results = features(spec);
    out.forms_seconds = seconds_since(t0);
    std::vector<size_t> good;
    std::ostringstream failures;
    for (size_t k = 0; k < models_.size(); ++k) {
        if (!results[k].note.empty())
            log_line(o, "[" + method + "] " + models_[k].name + ": " + results[k].note);
        if (results[k].ok) {
            good.push_back(k);
            out.cached += results[k].cached;
        } else {
            failures << models_[k].name << ": " << results[k].error << "\n";
        }
    }
    out.meshes = good.size();
    out.failed = models_.size() - good.size();
    io::write_file_atomic(dir + "/failures.txt", failures.str());
    char line[300];
    std::snprintf(line, sizeof line, "[%s] %zu meshes in %.1f s (%d from the cache, %zu failed)",
                  method.c_str(), models_.size(), out.forms_seconds, out.cached, out.failed);
    log_line(o, line);
    if (good.size() < 3)
        throw InputError(method + ": fewer than three meshes succeeded; see " + dir + "/failures.txt");

    // 2. Codebook.
    t0 = SteadyClock::now();
    const views::Codebook cb = codebook(spec, results, good);
    cb.save(dir + "/codebook.bin");  // the queries of an indexed collection (collection_index.h) need it
    out.codebook_seconds = seconds_since(t0);

    // 3. Descriptors (the words of every feature: in parallel, as a sharded run's), distances,
    // measures.
    t0 = SteadyClock::now();
    std::vector<std::vector<views::Histogram>> hist(good.size());
    ParallelOptions par;
    par.threads = o.threads;
    parallel_for(
        static_cast<std::ptrdiff_t>(good.size()),
        [&](std::ptrdiff_t i, int) {
            const size_t k = good[static_cast<size_t>(i)];
            views::ModelDescriptor d = views::make_descriptor(results[k].features, &cb, models_[k].path);
            views::write_descriptor(dir + "/descriptors/" + models_[k].name + ".cfvd", d);
            hist[static_cast<size_t>(i)] = std::move(d.histograms);
        },
        par);
    const Eigen::MatrixXf D = views::distance_matrix(hist, views::rotation_view_maps(), o.threads);
    out.distances_seconds = seconds_since(t0);
    finish_method(out, good, D);
    return out;
}

void Experiment::finish_method(MethodOutcome& out, const std::vector<size_t>& good,
                               const Eigen::MatrixXf& D) const {
    const auto t0 = SteadyClock::now();
    std::vector<std::string> labels;
    for (size_t k : good) labels.push_back(models_[k].label);
    io::write_distance_matrix(D, out.folder + "/distances.bin", out.folder + "/distances.csv");
    std::map<std::string, int> class_sizes;
    for (const std::string& l : labels) ++class_sizes[l];
    bool measurable = false;
    for (const auto& [label, count] : class_sizes) measurable = measurable || count > 2;
    if (measurable)
        out.evaluation = evaluate(D.cast<double>(), labels);
    else
        out.no_measures =
            "no class has more than two models among the " + std::to_string(good.size()) +
            " meshes that succeeded: the measures need three; the distances are in distances.bin";
    out.distances_seconds += seconds_since(t0);
    finish_measures(out, good, nlohmann::ordered_json::object());
}

void Experiment::finish_method(MethodOutcome& out, const std::vector<size_t>& good,
                               const Evaluation& evaluation, const nlohmann::ordered_json& extra) const {
    out.evaluation = evaluation;
    finish_measures(out, good, extra);
}

void Experiment::finish_measures(MethodOutcome& out, const std::vector<size_t>& good,
                                 const nlohmann::ordered_json& extra) const {
    const ExperimentOptions& o = options_;
    const auto t0 = SteadyClock::now();
    const canonical::MethodSpec& spec = out.spec;
    const std::string method = spec.folder();
    const std::string& dir = out.folder;
    std::ostringstream order;
    for (size_t k : good) order << models_[k].name << "," << models_[k].label << "\n";
    io::write_file_atomic(dir + "/models.csv", "name,class\n" + order.str());
    // Pose consistency against ground-truth correspondences (where the collection has them), on
    // the forms this run wrote; the correspondences name vertices of the original meshes, so not
    // on simplified ones.
    try {
        if (o.simplify == 0)
            out.pose_consistency = pose_consistency(models_, good, o.dataset, dir + "/forms",
                                                    &out.pose_consistency_pairs, o.threads);
    } catch (const std::exception& ex) {
        log_line(o, "[" + method + "] pose consistency not measured: " + ex.what());
    }
    const canonical::MethodSettings settings = spec.settings();
    nlohmann::ordered_json js;
    js["method"] = method;
    js["base"] = spec.name;
    js["beta"] = spec.method().parameter("beta") ? settings.number("beta") : 0.0;
    nlohmann::ordered_json more = {{"pose_consistency", out.pose_consistency},
                                   {"pose_consistency_pairs", out.pose_consistency_pairs}};
    for (const auto& [key, value] : extra.items()) more[key] = value;
    write_measures(o, dir, method, js, more, out);
    out.distances_seconds += seconds_since(t0);
    // The timings apart from the measures, so that metrics.json is equal for equal inputs.
    const nlohmann::ordered_json timings = {{"method", method},
                                            {"seconds",
                                             {{"forms_and_views", out.forms_seconds},
                                              {"codebook", out.codebook_seconds},
                                              {"distances_and_measures", out.distances_seconds}}}};
    io::write_file_atomic(dir + "/timings.json", timings.dump() + "\n");
}

std::vector<MethodOutcome> Experiment::run() const {
    std::vector<MethodOutcome> outcomes;
    for (const canonical::MethodSpec& m : options_.methods) outcomes.push_back(run_method(m));
    for (const FusedSpec& f : options_.fused) outcomes.push_back(run_fused(f));
    return outcomes;
}

MethodOutcome Experiment::run_fused(const FusedSpec& fused) const {
    const ExperimentOptions& o = options_;
    const auto t0 = SteadyClock::now();
    std::vector<std::string> folders;
    for (const std::string& m : fused.members) folders.push_back(canonical::parse_method_spec(m).folder());
    MethodOutcome out;
    out.label = fused.folder(folders);
    out.members = folders;
    const std::string dir = o.out + "/" + out.label;
    out.folder = dir;
    io::make_directories(dir);
    // Every member's matrix and model order; the fused matrix covers the models all members have.
    std::vector<Eigen::MatrixXd> full;
    std::vector<std::map<std::string, Eigen::Index>> index(folders.size());
    std::vector<std::pair<std::string, std::string>> first;  // (name, class) of the first member, in order
    for (size_t k = 0; k < folders.size(); ++k) {
        const std::string mdir = o.out + "/" + folders[k];
        full.push_back(io::read_distance_matrix(mdir + "/distances.bin"));
        const auto rows = io::read_csv(mdir + "/models.csv");
        for (size_t r = 1; r < rows.size(); ++r) {
            if (rows[r].size() < 2) continue;
            index[k][rows[r][0]] = static_cast<Eigen::Index>(index[k].size());
            if (k == 0) first.emplace_back(rows[r][0], rows[r][1]);
        }
        if (static_cast<Eigen::Index>(index[k].size()) != full.back().rows())
            throw InputError("'" + mdir + "/models.csv' does not match its distances.bin");
    }
    std::vector<std::pair<std::string, std::string>> models;
    for (const auto& nc : first) {
        bool everywhere = true;
        for (const auto& ix : index) everywhere = everywhere && ix.count(nc.first);
        if (everywhere) models.push_back(nc);
    }
    out.meshes = models.size();
    out.failed = models_.size() - models.size();
    if (models.size() < 3)
        throw InputError(out.label + ": fewer than three models have every member's distances");
    const Eigen::Index n = static_cast<Eigen::Index>(models.size());
    std::vector<Eigen::MatrixXf> parts;
    for (size_t k = 0; k < folders.size(); ++k) {
        Eigen::MatrixXf P(n, n);
        for (Eigen::Index i = 0; i < n; ++i)
            for (Eigen::Index j = 0; j < n; ++j)
                P(i, j) = static_cast<float>(full[k](index[k].at(models[static_cast<size_t>(i)].first),
                                                     index[k].at(models[static_cast<size_t>(j)].first)));
        parts.push_back(std::move(P));
    }
    const Eigen::MatrixXf D = fuse_distances(parts, fused.weights, fused.rule);
    io::write_distance_matrix(D, dir + "/distances.bin", dir + "/distances.csv");
    std::ostringstream order;
    std::vector<std::string> labels;
    std::map<std::string, int> class_sizes;
    for (const auto& [name, label] : models) {
        order << name << "," << label << "\n";
        labels.push_back(label);
        ++class_sizes[label];
    }
    io::write_file_atomic(dir + "/models.csv", "name,class\n" + order.str());
    bool measurable = false;
    for (const auto& [label, count] : class_sizes) measurable = measurable || count > 2;
    if (measurable)
        out.evaluation = evaluate(D.cast<double>(), labels);
    else
        out.no_measures = "no class has more than two models: the measures need three";
    out.distances_seconds = seconds_since(t0);
    nlohmann::ordered_json js;
    js["method"] = out.label;
    js["base"] = "fused";
    js["members"] = fused.members;
    js["weights"] = fused.weights;
    js["rule"] = fused.rule == FusionRule::GlobalMedian ? "median" : "row-zscore";
    write_measures(o, dir, out.label, js, {{"pose_consistency", -1}}, out);
    const nlohmann::ordered_json timings = {{"method", out.label},
                                            {"seconds", {{"fusion_and_measures", out.distances_seconds}}}};
    io::write_file_atomic(dir + "/timings.json", timings.dump() + "\n");
    return out;
}

std::string report_markdown(const ExperimentOptions& o, std::size_t meshes,
                            const std::vector<MethodOutcome>& outcomes, const std::string& pictures) {
    std::ostringstream report;
    report
        << "# Retrieval run\n\n"
        << meshes << " meshes from `" << o.dataset << "`, labels `" << o.labels << "`"
        << (o.simplify ? ", simplified to " + std::to_string(o.simplify) + " vertices" : std::string())
        << (o.noise > 0 ? ", noise " + std::to_string(o.noise) + " of the mean edge length" : std::string())
        << ".\n\n| method | NN | 1-Tier | 2-Tier | E-measure | DCG | pose consistency | meshes | failed | "
           "forms+views s | codebook s | distances s |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const MethodOutcome& m : outcomes) {
        const Measures& e = m.evaluation.micro;
        char row[400], cons[32] = "-";
        if (m.pose_consistency >= 0) std::snprintf(cons, sizeof cons, "%.3f", m.pose_consistency);
        if (m.no_measures.empty())
            std::snprintf(row, sizeof row,
                          "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %s | %zu | %zu | %.1f | %.1f | %.1f |\n",
                          m.name().c_str(), e.nn, e.first_tier, e.second_tier, e.e_measure, e.dcg, cons,
                          m.meshes, m.failed, m.forms_seconds, m.codebook_seconds, m.distances_seconds);
        else
            std::snprintf(row, sizeof row,
                          "| %s | - | - | - | - | - | %s | %zu | %zu | %.1f | %.1f | %.1f |\n",
                          m.name().c_str(), cons, m.meshes, m.failed, m.forms_seconds, m.codebook_seconds,
                          m.distances_seconds);
        report << row;
    }
    report << summary_markdown(outcomes);
    for (const MethodOutcome& m : outcomes)
        if (!m.no_measures.empty())
            report << "\nNo measures for " << m.name() << ": " << m.no_measures << ".\n";
    report << pictures;
    report
        << "\nPose consistency: mean over same-class pairs with ground-truth correspondences (corres/*.vts) "
           "of "
           "the RMS distance between corresponding vertices after the best rigid motion (or mirror image), "
           "relative to the RMS radius; lower = more pose removed.\n";
    report
        << "\nMicro averages (psbTable's definitions, normalised by C-1). Per method: `METHOD/metrics.json`, "
           "`METHOD/pr.csv`, `METHOD/distances.bin` (float32 row-major, rows as `METHOD/models.csv`), "
           "`METHOD/failures.txt`.\n";
    return report.str();
}

std::string summary_markdown(const std::vector<MethodOutcome>& outcomes) {
    struct Column {
        const char* title;
        double Measures::*value;
    };
    static const Column columns[] = {{"NN", &Measures::nn},
                                     {"1-Tier", &Measures::first_tier},
                                     {"2-Tier", &Measures::second_tier},
                                     {"E-measure", &Measures::e_measure},
                                     {"DCG", &Measures::dcg}};
    // Compared as the table shows them (three decimals): a difference the table hides is no win.
    const auto shown = [](double v) { return std::llround(v * 1000.0); };
    std::vector<const MethodOutcome*> measured;
    for (const MethodOutcome& m : outcomes)
        if (m.no_measures.empty()) measured.push_back(&m);
    if (measured.size() < 2) return {};
    std::ostringstream out;
    char figure[32];
    out << "\n## Summary\n\nBest per measure:";
    for (const Column& c : columns) {
        long long best = shown(measured.front()->evaluation.micro.*c.value);
        for (const MethodOutcome* m : measured) best = std::max(best, shown(m->evaluation.micro.*c.value));
        std::string names;
        for (const MethodOutcome* m : measured)
            if (shown(m->evaluation.micro.*c.value) == best) names += (names.empty() ? "" : ", ") + m->name();
        std::snprintf(figure, sizeof figure, "%.3f", best / 1000.0);
        out << (&c == columns ? " " : "; ") << c.title << " " << names << " (" << figure << ")";
    }
    out << ".\n";
    for (const MethodOutcome* f : measured) {
        if (f->members.empty()) continue;
        std::vector<const MethodOutcome*> members;
        for (const std::string& folder : f->members)
            for (const MethodOutcome* m : measured)
                if (m->members.empty() && m->spec.folder() == folder) members.push_back(m);
        if (members.size() != f->members.size()) continue;  // a member without measures
        std::string behind;
        for (const Column& c : columns) {
            const MethodOutcome* top = members.front();
            for (const MethodOutcome* m : members)
                if (shown(m->evaluation.micro.*c.value) > shown(top->evaluation.micro.*c.value)) top = m;
            const long long mine = shown(f->evaluation.micro.*c.value),
                            theirs = shown(top->evaluation.micro.*c.value);
            if (mine > theirs) continue;
            char text[160];
            std::snprintf(text, sizeof text, "%s %.3f %s %s's %.3f", c.title, mine / 1000.0,
                          mine == theirs ? "ties" : "against", top->name().c_str(), theirs / 1000.0);
            behind += (behind.empty() ? "" : "; ") + std::string(text);
        }
        if (behind.empty())
            out << "\n" << f->name() << " beats every member on all five measures.\n";
        else
            out << "\n"
                << f->name() << " does not beat its best member on this collection: " << behind
                << ". Here the better member alone is at least as good on those measures (docs/retrieval.md, "
                   "\"Fused methods\").\n";
    }
    return out.str();
}

namespace {

/// min over B and its mirror image of the RMS residual of the best rigid motion of A onto B,
/// for point sets A and B centred on their means (numerics::align_rigid's rms, with its mirror
/// image's, in two passes and no copies: the mirror image's cross-covariance is H with its first
/// row negated, exactly).
double rigid_or_mirror_rms(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
    const Eigen::Index n = A.rows();
    const double *a0 = A.col(0).data(), *a1 = A.col(1).data(), *a2 = A.col(2).data();
    const double *b0 = B.col(0).data(), *b1 = B.col(1).data(), *b2 = B.col(2).data();
    Eigen::Matrix3d H = numerics::cross_covariance(A, B);
    const Eigen::Matrix3d R = numerics::best_rotation(H);
    H.row(0) *= -1;
    Eigen::Matrix3d M = numerics::best_rotation(H);
    M.col(0) *= -1;  // the rotation of the mirror image, applied to A itself
    double s = 0, sm = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
        const double a[3] = {a0[k], a1[k], a2[k]}, b[3] = {b0[k], b1[k], b2[k]};
        double d = 0, dm = 0;
        for (int i = 0; i < 3; ++i) {
            const double e = R(i, 0) * a[0] + R(i, 1) * a[1] + R(i, 2) * a[2] - b[i];
            const double em = M(i, 0) * a[0] + M(i, 1) * a[1] + M(i, 2) * a[2] - b[i];
            d += e * e;
            dm += em * em;
        }
        s += d;
        sm += dm;
    }
    return std::sqrt(std::min(s, sm) / static_cast<double>(n));
}

}  // namespace

double pose_consistency(const std::vector<Model>& models, const std::vector<size_t>& good,
                        const std::string& dataset, const std::string& forms_dir, int* pairs, int threads) {
    // Per model, in parallel: its corresponding points centred on their mean (none when it has no
    // correspondences or one names a vertex the form does not have) and their RMS radius.
    const size_t n = good.size();
    std::vector<Eigen::MatrixXd> P(n);
    std::vector<double> radius(n, 0.0);
    ParallelOptions par;
    par.threads = threads;
    parallel_for(
        static_cast<std::ptrdiff_t>(n),
        [&](std::ptrdiff_t a, int) {
            const Model& m = models[good[static_cast<size_t>(a)]];
            const std::vector<int> vts = read_vts(dataset, m.name);
            if (vts.empty()) return;
            const Eigen::MatrixXd V = io::read_mesh(forms_dir + "/" + m.name + ".ply").V;
            Eigen::MatrixXd Q(static_cast<Eigen::Index>(vts.size()), 3);
            for (size_t k = 0; k < vts.size(); ++k) {
                if (vts[k] < 0 || vts[k] >= V.rows()) return;
                Q.row(static_cast<Eigen::Index>(k)) = V.row(vts[k]);
            }
            Q = (Q.rowwise() - Q.colwise().mean()).eval();
            radius[static_cast<size_t>(a)] = std::sqrt(Q.squaredNorm() / static_cast<double>(Q.rows()));
            P[static_cast<size_t>(a)] = std::move(Q);
        },
        par);
    // Same-class pairs (a, b > a), a row per task; summed afterwards in the order of the pairs.
    std::vector<std::vector<double>> row(n);
    parallel_for(
        static_cast<std::ptrdiff_t>(n),
        [&](std::ptrdiff_t a_, int) {
            const auto a = static_cast<size_t>(a_);
            if (P[a].rows() == 0) return;
            for (size_t b = a + 1; b < n; ++b) {
                if (models[good[a]].label != models[good[b]].label || P[b].rows() != P[a].rows()) continue;
                row[a].push_back(rigid_or_mirror_rms(P[a], P[b]) / radius[b]);
            }
        },
        par);
    double sum = 0;
    *pairs = 0;
    for (const auto& r : row)
        for (double v : r) {
            sum += v;
            ++*pairs;
        }
    return *pairs ? sum / *pairs : -1.0;
}

}  // namespace canonform::retrieval
