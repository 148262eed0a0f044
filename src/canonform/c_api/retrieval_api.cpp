// SPDX-License-Identifier: GPL-3.0-or-later
// canonform C API (canonform.h): retrieval - the measures of a distance matrix, distance-matrix and
// labels files, and whole experiments as `canonform retrieve` runs them.
#include "canonform/c_api/c_api_support.h"
#include "canonform/c_api/json_text.h"

#ifdef CANONFORM_C_API_RETRIEVAL
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/retrieval/retrieval_measures.h"
#endif

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace canonform;
using namespace canonform::c_api;

namespace {

#ifdef CANONFORM_C_API_RETRIEVAL
/// JSON text with invalid UTF-8 (class names, paths) replaced by U+FFFD.
std::string dump(const nlohmann::ordered_json& j) {
    return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

/// The evaluation as `canonform evaluate --json` prints it (micro, macro, classes, precision),
/// then recall, the classes left out, and the five micro measures at the top for short access.
nlohmann::ordered_json evaluation_json(const retrieval::Evaluation& e) {
    nlohmann::ordered_json classes = nlohmann::ordered_json::object();
    for (size_t k = 0; k < e.classes.size(); ++k) classes[e.classes[k]] = retrieval::to_json(e.per_class[k]);
    nlohmann::ordered_json j = {{"micro", retrieval::to_json(e.micro)},
                                {"macro", retrieval::to_json(e.macro)},
                                {"classes", classes},
                                {"precision", e.precision}};
    j["recall"] = e.recall;
    j["skipped_classes"] = e.skipped_classes;
    const nlohmann::ordered_json micro = retrieval::to_json(e.micro);
    for (const auto& [k, v] : micro.items()) j[k] = v;
    return j;
}

std::vector<std::string> method_list(const std::string& s) {
    std::vector<std::string> out;
    size_t b = 0;
    while (b <= s.size()) {
        const size_t e = std::min(s.find(',', b), s.size());
        if (e > b) out.push_back(s.substr(b, e - b));
        b = e + 1;
    }
    if (out.empty()) throw InputError("methods is empty: name at least one method");
    return out;
}
#endif

#ifndef CANONFORM_C_API_RETRIEVAL
[[noreturn]] void no_retrieval() {
    throw Unsupported(
        "this build of canonform has no retrieval area (configure with CANONFORM_RETRIEVAL=ON)");
}
#endif

}  // namespace

extern "C" {

int canonform_evaluate(const double* D, int64_t rows, int64_t cols, const char* D_path,
                       const char* const* labels, int64_t nlabels, const char* labels_path, char** json) {
    clear_outputs(json);
    return guarded([&] {
        require_out(json, "json");
#ifdef CANONFORM_C_API_RETRIEVAL
        const Eigen::MatrixXd d = D_path ? io::read_distance_matrix(D_path) : matrix_in(D, rows, cols, "D");
        std::vector<std::string> l;
        if (labels_path) {
            for (const auto& row : io::read_labels(labels_path)) l.push_back(row.label);
        } else {
            if (nlabels < 0 || (nlabels > 0 && !labels)) throw InputError("labels: NULL or a negative count");
            for (int64_t k = 0; k < nlabels; ++k) l.push_back(text_in(labels[k], "a label"));
        }
        *json = text_out(dump(evaluation_json(retrieval::evaluate(d, l))));
#else
        (void)D, (void)rows, (void)cols, (void)D_path, (void)labels, (void)nlabels, (void)labels_path;
        no_retrieval();
#endif
    });
}

int canonform_read_distance_matrix(const char* path, canonform_array** D) {
    clear_outputs(D);
    return guarded([&] {
        require_out(D, "D");
#ifdef CANONFORM_C_API_RETRIEVAL
        const Eigen::MatrixXd M = io::read_distance_matrix(text_in(path, "path"));
        ArrayPtr a(new_array(CANONFORM_FLOAT32, 2, M.rows(), M.cols()));
        Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            a.data<float>(), M.rows(), M.cols()) = M.cast<float>();
        *D = a.release();
#else
        (void)path;
        no_retrieval();
#endif
    });
}

int canonform_read_labels(const char* path, char** json) {
    clear_outputs(json);
    return guarded([&] {
        require_out(json, "json");
#ifdef CANONFORM_C_API_RETRIEVAL
        nlohmann::ordered_json j = nlohmann::ordered_json::array();
        for (const auto& row : io::read_labels(text_in(path, "path"))) j.push_back({row.path, row.label});
        *json = text_out(dump(j));
#else
        (void)path;
        no_retrieval();
#endif
    });
}

void canonform_retrieve_options_init(canonform_retrieve_options* o) {
    if (!o) return;
    std::memset(o, 0, sizeof *o);
    o->methods = "none,euclidean-N";
    o->words = 1500;
    o->codebook = "kmeans";
#ifdef CANONFORM_C_API_RETRIEVAL
    o->codebook_sample = views::kDefaultCodebookSample;
#endif
}

int canonform_retrieve(const canonform_retrieve_options* options, canonform_progress_fn progress,
                       void* progress_user, canonform_log_fn log, void* log_user, char** result) {
    clear_outputs(result);
    return guarded([&] {
        require_out(result, "result");
        if (!options) throw InputError("options is NULL");
#ifdef CANONFORM_C_API_RETRIEVAL
        const canonform_retrieve_options& a = *options;
        // The ranges of `canonform retrieve`'s options.
        check_range("words", a.words, 1, 1000000);
        check_range("codebook_sample", a.codebook_sample, 0, 2000000000LL);
        check_range("simplify", a.simplify, 0, 100000000);
        if (!std::isfinite(a.noise) || a.noise < 0 || a.noise > 10)
            throw InputError("noise must be a finite number between 0 and 10, got " +
                             (std::isnan(a.noise)   ? std::string("nan")
                              : std::isinf(a.noise) ? std::string(a.noise > 0 ? "inf" : "-inf")
                                                    : json_number(a.noise)));
        check_range("seed", a.seed, 0, 4294967295LL);
        check_range("threads", a.threads, 0, 1024);

        retrieval::ExperimentOptions o;
        o.dataset = text_in(a.dataset, "dataset");
        o.out = text_in(a.out, "out");
        o.labels = a.labels ? std::string(a.labels) : o.dataset + "/labels.csv";
        o.words = static_cast<int>(a.words);
        o.codebook_training.sample = a.codebook_sample;
        const std::string codebook = a.codebook ? a.codebook : "kmeans";
        if (codebook == "kmeans" || codebook == "lloyd" || codebook == "random")
            o.codebook_training.method = views::parse_codebook_method(codebook);
        else
            o.codebook = codebook;  // a codebook file for every method
        o.simplify = static_cast<int>(a.simplify);
        o.noise = a.noise;
        o.seed = static_cast<std::uint64_t>(a.seed);
        o.threads = a.threads;
        o.repair = a.repair != 0;
        if (a.sift) o.views.sift.backend = views::parse_sift_backend(a.sift);
        for (const std::string& m : method_list(a.methods ? a.methods : "none,euclidean-N")) {
            if (retrieval::is_fused_spec(m))
                o.fused.push_back(retrieval::parse_fused_spec(m));
            else
                o.methods.push_back(canonical::parse_method_spec(m));
        }
        const ProgressFn report = progress_in(progress, progress_user);
        if (report)
            o.progress = [report](const std::string& method) -> ProgressFn {
                return
                    [=](double f, const char* stage) { return report(f, (method + ": " + stage).c_str()); };
            };
        if (log)
            o.log = [log, log_user](const std::string& line) {
                if (!log(log_user, line.c_str())) throw Cancelled();
            };

        const retrieval::Experiment experiment(o);
        const std::vector<retrieval::MethodOutcome> outcomes = experiment.run();
        const std::size_t meshes = experiment.models().size();
        const std::string report_md = retrieval::report_markdown(o, meshes, outcomes, "");
        io::write_file_atomic(o.out + "/report.md", report_md);

        nlohmann::ordered_json per_method = nlohmann::ordered_json::object();
        for (const retrieval::MethodOutcome& m : outcomes) {
            nlohmann::ordered_json d = {
                {"folder", m.folder}, {"meshes", m.meshes}, {"failed", m.failed}, {"cached", m.cached}};
            d["measures"] =
                m.no_measures.empty() ? evaluation_json(m.evaluation) : nlohmann::ordered_json(nullptr);
            d["no_measures"] = m.no_measures;
            d["pose_consistency"] = m.pose_consistency >= 0 ? nlohmann::ordered_json(m.pose_consistency)
                                                            : nlohmann::ordered_json(nullptr);
            d["pose_consistency_pairs"] = m.pose_consistency_pairs;
            d["forms_seconds"] = m.forms_seconds;
            d["codebook_seconds"] = m.codebook_seconds;
            d["distances_seconds"] = m.distances_seconds;
            per_method[m.name()] = d;
        }
        const nlohmann::ordered_json out = {{"out", o.out}, {"report", report_md}, {"methods", per_method}};
        *result = text_out(dump(out));
#else
        (void)progress, (void)progress_user, (void)log, (void)log_user;
        no_retrieval();
#endif
    });
}

}  // extern "C"
