#include "retrieve_command.h"

#include "canonform/views/descriptor_file.h"
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/numerics/rigid_alignment.h"
#include "canonform/retrieval/retrieval_measures.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#include "grid.h"
#include "canonform/io/mesh_io.h"
#include "canonform/surface/simplify.h"
#include "views_commands.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <random>
#include <sstream>
#include <sys/stat.h>
#include <thread>

namespace canonform::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 1469598103934665603ULL) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    return h;
}

std::string hex(std::uint64_t v) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void make_dir(const std::string& d) {
    std::string partial;
    std::istringstream parts(d);
    std::string piece;
    if (!d.empty() && d[0] == '/') partial = "/";
    while (std::getline(parts, piece, '/')) {
        if (piece.empty()) continue;
        partial += piece + "/";
        mkdir(partial.c_str(), 0755);
    }
    struct stat st {};
    if (stat(d.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw std::runtime_error("cannot create the folder '" + d + "'");
}

struct Model {
    std::string path, label, name;
    std::uint64_t hash = 0;
};

struct MeshResult {
    bool ok = false;
    bool cached = false;
    std::string error;
    std::vector<views::SiftDescriptors> features;
    std::vector<int> counts;
};

/// Seeded vertex noise: every coordinate moves by N(0, (sigma * mean edge length)^2).
void add_noise(io::MeshData& m, double sigma, std::uint64_t seed) {
    const Eigen::MatrixXi E = unique_edges(m.F);
    double mean = 0;
    for (Eigen::Index e = 0; e < E.rows(); ++e) mean += (m.V.row(E(e, 0)) - m.V.row(E(e, 1))).norm();
    mean /= std::max<Eigen::Index>(1, E.rows());
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, sigma * mean);
    for (Eigen::Index i = 0; i < m.V.rows(); ++i)
        for (int c = 0; c < 3; ++c) m.V(i, c) += g(rng);
}

/// A method of the run: "none", "euclidean-A", ..., optionally with a parameter
/// ("euclidean-N:beta=50"). `dir` names its folder in the run ("euclidean-N_beta50").
struct MethodSpec {
    std::string spec, base, dir;
    double beta = 0;  ///< 0 = the variant's default
    bool euclidean() const { return base == "euclidean-A" || base == "euclidean-N"; }
    EuclideanCanonicalFormOptions euclidean_options() const {
        EuclideanCanonicalFormOptions e;
        e.variant = base == "euclidean-A" ? CanonicalVariant::A : CanonicalVariant::N;
        e.beta = beta;
        return e;
    }
    /// What the cached results depend on: the method and, for the Euclidean forms, the beta used.
    std::string cache_key() const {
        if (!euclidean()) return base;
        std::ostringstream k;
        k.precision(17);
        k << base << "|beta=" << euclidean_options().effective_beta();
        return k.str();
    }
};

Eigen::MatrixXd canonical(const MethodSpec& method, const io::MeshData& m) {
    if (method.base == "none") return m.V;
    if (method.euclidean()) {
        return euclidean_canonical_form(m.V, m.F, method.euclidean_options()).V;
    }
    GeodesicCanonicalFormOptions o;
    o.threads = 1;  // the meshes run in parallel
    o.method = method.base == "geodesic-ls" ? GeodesicMds::LeastSquares
               : method.base == "geodesic-classical" ? GeodesicMds::Classical
                                                 : GeodesicMds::Fast;
    return geodesic_canonical_form(m.V, m.F, o).V;
}

MeshResult process(const Model& model, const MethodSpec& method, const RetrieveOptions& o, const std::string& dir,
                   const std::string& cache) {
    MeshResult r;
    std::ostringstream params;
    params << method.cache_key() << "|simplify=" << o.simplify << "|noise=" << o.noise << "|seed=" << o.seed << "|views=v1";
    const std::string key = cache + "/" + hex(fnv1a(params.str(), model.hash)) + ".cfvd";
    const std::string form = dir + "/forms/" + model.name + ".ply";
    const std::string cached_form = key.substr(0, key.size() - 5) + ".ply";
    try {
        // A cache hit also restores the form (forms/ may hold one of other parameters, or none,
        // and the pose consistency and the grid read it); an entry without its form is recomputed.
        if (access(key.c_str(), R_OK) == 0 && access(cached_form.c_str(), R_OK) == 0) {
            io::write_file_atomic(form, slurp(cached_form));
            views::ModelDescriptor d = views::read_descriptor(key);
            r.features = std::move(d.raw);
            r.counts = d.keypoints_per_view;
            r.ok = r.cached = true;
            return r;
        }
        io::MeshData m = io::read_mesh(model.path);
        if (o.simplify > 0 && m.V.rows() > o.simplify) m = io::simplify_mesh(m, o.simplify);
        if (o.noise > 0) add_noise(m, o.noise, o.seed ^ model.hash);
        const Eigen::MatrixXd X = canonical(method, m);
        io::write_ply(form, X, m.F);
        io::write_file_atomic(cached_form, slurp(form));
        const views::ViewSet vs = views::compute_views(X, m.F);
        views::ModelDescriptor d;
        d.source = model.path;
        d.views = static_cast<int>(vs.features.size());
        d.keypoints_per_view = vs.keypoint_counts();
        d.raw = vs.features;
        views::write_descriptor(key, d);
        r.features = vs.features;
        r.counts = d.keypoints_per_view;
        r.ok = true;
    } catch (const std::exception& e) {
        r.error = e.what();
    }
    return r;
}


/// Ground-truth correspondences of a model: DATASET/corres/NAME.vts, line k = the 1-based vertex
/// at template point k (empty if the file does not exist).
std::vector<int> read_vts(const std::string& dataset, const std::string& name) {
    std::ifstream in(dataset + "/corres/" + name + ".vts");
    std::vector<int> v;
    for (int x; in >> x;) v.push_back(x - 1);
    return v;
}

/// Pose consistency: over all same-class pairs with correspondences, the RMS distance between
/// corresponding vertices of the two forms after the best rigid motion (or mirror image: MDS
/// fixes a form only up to one), relative to the RMS radius of the second; the mean over pairs.
/// Returns -1 if no pair has correspondences.
double pose_consistency(const std::vector<Model>& models, const std::vector<size_t>& good, const std::string& dataset,
                        const std::string& forms_dir, int* pairs) {
    std::vector<std::vector<int>> vts(models.size());
    std::vector<Eigen::MatrixXd> V(models.size());
    for (size_t k : good) {
        vts[k] = read_vts(dataset, models[k].name);
        if (!vts[k].empty()) V[k] = io::read_mesh(forms_dir + "/" + models[k].name + ".ply").V;
    }
    double sum = 0;
    *pairs = 0;
    for (size_t a = 0; a < good.size(); ++a) {
        for (size_t b = a + 1; b < good.size(); ++b) {
            const size_t i = good[a], j = good[b];
            if (models[i].label != models[j].label || vts[i].empty() || vts[i].size() != vts[j].size()) continue;
            Eigen::MatrixXd P(static_cast<Eigen::Index>(vts[i].size()), 3), Q(P.rows(), 3);
            bool valid = true;
            for (size_t k = 0; k < vts[i].size() && valid; ++k) {
                valid = vts[i][k] >= 0 && vts[i][k] < V[i].rows() && vts[j][k] >= 0 && vts[j][k] < V[j].rows();
                if (valid) {
                    P.row(static_cast<Eigen::Index>(k)) = V[i].row(vts[i][k]);
                    Q.row(static_cast<Eigen::Index>(k)) = V[j].row(vts[j][k]);
                }
            }
            if (!valid) continue;
            const double radius = std::sqrt((Q.rowwise() - Q.colwise().mean()).squaredNorm() / static_cast<double>(Q.rows()));
            Eigen::MatrixXd M = P;
            M.col(0) *= -1;
            sum += std::min(align_rigid(P, Q).rms, align_rigid(M, Q).rms) / radius;
            ++*pairs;
        }
    }
    return *pairs ? sum / *pairs : -1.0;
}

}  // namespace

MethodSpec parse_method(const std::string& spec) {
    MethodSpec m;
    m.spec = spec;
    const auto colon = spec.find(':');
    m.base = spec.substr(0, colon);
    if (m.base != "none" && m.base != "euclidean-A" && m.base != "euclidean-N" && m.base != "geodesic-ls" &&
        m.base != "geodesic-classical" && m.base != "geodesic-fast")
        throw InputError("unknown method '" + m.base + "' (none, euclidean-A, euclidean-N, geodesic-ls, "
                         "geodesic-classical, geodesic-fast)");
    m.dir = m.base;
    if (colon == std::string::npos) return m;
    const std::string param = spec.substr(colon + 1);
    if (!m.euclidean() || param.rfind("beta=", 0) != 0)
        throw InputError("method '" + spec + "': only euclidean-A and euclidean-N take a parameter, beta=B");
    const std::string value = param.substr(5);
    char* end = nullptr;
    m.beta = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !(m.beta > 0) || !std::isfinite(m.beta))
        throw InputError("method '" + spec + "': beta must be a positive number, got '" + value + "'");
    m.dir = m.base + "_beta" + value;
    return m;
}

int retrieve_command(const RetrieveOptions& o) {
    if (o.methods.empty()) throw InputError("name at least one --method");
    std::vector<MethodSpec> specs;
    for (const auto& m : o.methods) {
        specs.push_back(parse_method(m));
        for (size_t k = 0; k + 1 < specs.size(); ++k)
            if (specs[k].dir == specs.back().dir) throw InputError("method '" + m + "' is named twice");
    }
    // The collection: labels.csv rows in order, paths relative to the dataset folder.
    std::vector<Model> models;
    {
        std::istringstream in(slurp(o.labels));
        std::string line;
        while (std::getline(in, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            const auto comma = line.rfind(',');
            if (line.empty() || comma == std::string::npos) continue;
            Model m;
            m.path = o.dataset + "/" + line.substr(0, comma);
            m.label = line.substr(comma + 1);
            if (m.label == "class" && models.empty() && line.substr(0, comma) == "path") continue;  // header
            const auto slash = m.path.find_last_of('/');
            const auto dot = m.path.find_last_of('.');
            m.name = m.path.substr(slash + 1, dot == std::string::npos || dot < slash ? std::string::npos : dot - slash - 1);
            m.hash = fnv1a(slurp(m.path));
            models.push_back(m);
        }
    }
    if (models.size() < 3) throw InputError("the collection needs at least three meshes");
    make_dir(o.out + "/cache");
    {
        // The collection as this run read it (name, class, mesh), for `canonform grid`.
        std::ostringstream c;
        c << "name,class,path\n";
        for (const Model& m : models) c << m.name << "," << m.label << "," << m.path << "\n";
        io::write_file_atomic(o.out + "/collection.csv", c.str());
    }
    const int threads = o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    const bool tty = isatty(2);
    std::ostringstream report;
    report << "# Retrieval run\n\n" << models.size() << " meshes from `" << o.dataset << "`, labels `" << o.labels
           << "`" << (o.simplify ? ", simplified to " + std::to_string(o.simplify) + " vertices" : std::string())
           << (o.noise > 0 ? ", noise " + std::to_string(o.noise) + " of the mean edge length" : std::string())
           << ".\n\n| method | NN | 1-Tier | 2-Tier | E-measure | DCG | pose consistency | meshes | failed | "
              "forms+views s | codebook s | distances s |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";

    for (const MethodSpec& spec : specs) {
        const std::string& method = spec.dir;
        const std::string dir = o.out + "/" + method;
        make_dir(dir + "/forms");
        make_dir(dir + "/descriptors");
        // 1. Per mesh, in parallel: canonical form and the SIFT features of its views (cached).
        auto t0 = Clock::now();
        std::vector<MeshResult> results(models.size());
        std::atomic<size_t> next{0}, done{0};
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t)
            pool.emplace_back([&] {
                for (size_t k; (k = next++) < models.size(); ++done)
                    results[k] = process(models[k], spec, o, dir, o.out + "/cache");
            });
        while (done < models.size()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(tty ? 300 : 2000));
            const double el = since(t0), rate = done / std::max(el, 1e-9);
            if (tty)
                std::fprintf(stderr, "\r[%s] %zu/%zu meshes, %.2f/s, %.0f s left   ", method.c_str(), done.load(),
                             models.size(), rate, rate > 0 ? (models.size() - done) / rate : 0.0);
        }
        for (auto& th : pool) th.join();
        const double forms_s = since(t0);
        std::vector<size_t> good;
        std::ostringstream failures;
        int cached = 0;
        for (size_t k = 0; k < models.size(); ++k) {
            if (results[k].ok) {
                good.push_back(k);
                cached += results[k].cached;
            } else {
                failures << models[k].name << ": " << results[k].error << "\n";
            }
        }
        io::write_file_atomic(dir + "/failures.txt", failures.str());
        std::fprintf(stderr, "\r[%s] %zu meshes in %.1f s (%d from the cache, %zu failed)          \n", method.c_str(),
                     models.size(), forms_s, cached, models.size() - good.size());
        if (good.size() < 3) throw InputError(method + ": fewer than three meshes succeeded; see " + dir + "/failures.txt");

        // 2. Codebook (given, or trained on this method's features; cached by its inputs).
        t0 = Clock::now();
        views::Codebook cb;
        if (!o.codebook.empty()) {
            cb = views::Codebook::load(o.codebook);
        } else {
            std::uint64_t h = fnv1a(spec.cache_key() + "|words=" + std::to_string(o.words) + "|seed=" + std::to_string(o.seed));
            Eigen::Index rows = 0;
            for (size_t k : good) {
                h = fnv1a(hex(models[k].hash), h);
                for (const auto& f : results[k].features) rows += f.rows();
            }
            const std::string cb_path = o.out + "/cache/codebook_" + hex(h) + ".bin";
            if (access(cb_path.c_str(), R_OK) == 0) {
                cb = views::Codebook::load(cb_path);
            } else {
                views::SiftDescriptors all(rows, 128);
                Eigen::Index r = 0;
                for (size_t k : good)
                    for (const auto& f : results[k].features) {
                        all.middleRows(r, f.rows()) = f;
                        r += f.rows();
                    }
                views::CodebookOptions co;
                co.words = o.words;
                co.seed = o.seed;
                cb = views::Codebook::train(all, co);
                cb.save(cb_path);
            }
        }
        const double codebook_s = since(t0);

        // 3. Descriptors, distances, measures.
        t0 = Clock::now();
        std::vector<std::vector<views::Histogram>> hist;
        std::vector<std::string> labels;
        std::ostringstream order;
        for (size_t k : good) {
            views::ModelDescriptor d;
            d.source = models[k].path;
            d.keypoints_per_view = results[k].counts;
            d.codebook_words = cb.size();
            for (const auto& f : results[k].features) d.histograms.push_back(views::histogram(cb.assign(f)));
            views::write_descriptor(dir + "/descriptors/" + models[k].name + ".cfvd", d);
            hist.push_back(std::move(d.histograms));
            labels.push_back(models[k].label);
            order << models[k].name << "," << models[k].label << "\n";
        }
        const Eigen::MatrixXf D = views::distance_matrix(hist, views::rotation_view_maps(), threads);
        write_distance_matrix(D, dir + "/distances.bin", dir + "/distances.csv");
        io::write_file_atomic(dir + "/models.csv", "name,class\n" + order.str());
        const retrieval::Evaluation e = retrieval::evaluate(D.cast<double>(), labels);
        const double distances_s = since(t0);
        // Pose consistency against ground-truth correspondences (where the collection has them),
        // on the forms this run wrote (forms/; a form missing there is reported, not measured).
        int pairs = 0;
        double consistency = -1;
        try {
            // The correspondences name vertices of the original meshes: not of simplified ones.
            if (o.simplify == 0) consistency = pose_consistency(models, good, o.dataset, dir + "/forms", &pairs);
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "[%s] pose consistency not measured: %s\n", method.c_str(), ex.what());
        }
        std::ostringstream js, pr;
        js << "{\"method\": \"" << method << "\", \"base\": \"" << spec.base << "\", \"beta\": "
           << (spec.euclidean() ? spec.euclidean_options().effective_beta() : 0.0) << ", \"meshes\": " << good.size() << ", \"failed\": "
           << models.size() - good.size() << ", \"micro\": " << retrieval::to_json(e.micro)
           << ", \"macro\": " << retrieval::to_json(e.macro) << ", \"pose_consistency\": " << consistency
           << ", \"pose_consistency_pairs\": " << pairs << ", \"seconds\": {\"forms_and_views\": " << forms_s
           << ", \"codebook\": " << codebook_s << ", \"distances_and_measures\": " << distances_s << "}}\n";
        io::write_file_atomic(dir + "/metrics.json", js.str());
        pr << "recall,precision\n";
        for (size_t k = 0; k < e.recall.size(); ++k) pr << e.recall[k] << "," << e.precision[k] << "\n";
        io::write_file_atomic(dir + "/pr.csv", pr.str());
        char row[400], cons[32] = "-";
        if (consistency >= 0) std::snprintf(cons, sizeof cons, "%.3f", consistency);
        std::snprintf(row, sizeof row, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %s | %zu | %zu | %.1f | %.1f | %.1f |\n",
                      method.c_str(), e.micro.nn, e.micro.first_tier, e.micro.second_tier, e.micro.e_measure,
                      e.micro.dcg, cons, good.size(), models.size() - good.size(), forms_s, codebook_s, distances_s);
        report << row;
        std::fprintf(stderr, "[%s] NN %.3f, 1-tier %.3f, 2-tier %.3f, E %.3f, DCG %.3f\n", method.c_str(), e.micro.nn,
                     e.micro.first_tier, e.micro.second_tier, e.micro.e_measure, e.micro.dcg);
    }
    // Precision-recall curves of all methods on one plot (Debian's python3-matplotlib).
    const std::string plot = std::string(CANONFORM_TOOLS_DIR) + "/plot_pr.py";
    const std::string cmd = "/usr/bin/python3 '" + plot + "' '" + o.out + "' > /dev/null 2>&1";
    if (access(plot.c_str(), R_OK) == 0 && std::system(cmd.c_str()) == 0)
        report << "\n![precision-recall](pr.png)\n";
    else
        report << "\n(No precision-recall plot: run /usr/bin/python3 tools/plot_pr.py " << o.out << ".)\n";
    // Originals beside their canonical forms, one model per class (the paper's Fig. 8).
    std::vector<std::string> form_methods;
    for (const MethodSpec& spec : specs)
        if (spec.base != "none") form_methods.push_back(spec.dir);
    if (!form_methods.empty()) {
        try {
            GridOptions g;
            g.run = o.out;
            g.methods = form_methods;
            g.panel = form_methods.size() > 4 ? 110 : 150;
            write_grid(o.out + "/grid.png", g);
            report << "\n![originals (first row) and their canonical forms, one model per class; colour = height "
                      "along the original's longest axis](grid.png)\n";
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "retrieve: no grid picture: %s\n", ex.what());
            report << "\n(No grid picture: " << ex.what() << ")\n";
        }
    }
    report << "\nPose consistency: mean over same-class pairs with ground-truth correspondences (corres/*.vts) of "
              "the RMS distance between corresponding vertices after the best rigid motion (or mirror image), "
              "relative to the RMS radius; lower = more pose removed.\n";
    report << "\nMicro averages (psbTable's definitions, normalised by C-1). Per method: `METHOD/metrics.json`, "
              "`METHOD/pr.csv`, `METHOD/distances.bin` (float32 row-major, rows as `METHOD/models.csv`), "
              "`METHOD/failures.txt`.\n";
    io::write_file_atomic(o.out + "/report.md", report.str());
    std::cout << report.str();
    return 0;
}

}  // namespace canonform::cli
