// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module: retrieval - the measures of a distance matrix and whole experiments.
#include "bindings.h"
#include "support.h"

#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/retrieval/retrieval_measures.h"

#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <tuple>
#include <vector>

namespace canonform::python {

namespace {

/// A JSON value as Python objects (dicts keep the JSON's order).
py::object from_json(const nlohmann::ordered_json& j) {
    switch (j.type()) {
    case nlohmann::ordered_json::value_t::null: return py::none();
    case nlohmann::ordered_json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::ordered_json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::ordered_json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::ordered_json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::ordered_json::value_t::string: return text(j.get<std::string>());
    case nlohmann::ordered_json::value_t::array: {
        py::list l;
        for (const auto& x : j) l.append(from_json(x));
        return l;
    }
    case nlohmann::ordered_json::value_t::object: {
        py::dict d;
        for (const auto& [k, v] : j.items()) d[text(k)] = from_json(v);
        return d;
    }
    default: return py::none();
    }
}

bool is_path(const py::handle& o) {
    return py::isinstance<py::str>(o) || py::isinstance<py::bytes>(o) ||
           py::isinstance(o, py::module_::import("os").attr("PathLike"));
}

/// The evaluation as `canonform evaluate --json` prints it (micro, macro, classes, precision),
/// then recall, the classes left out, and the five micro measures at the top for short access.
py::dict evaluation_dict(const retrieval::Evaluation& e) {
    nlohmann::ordered_json classes = nlohmann::ordered_json::object();
    for (size_t k = 0; k < e.classes.size(); ++k) classes[e.classes[k]] = retrieval::to_json(e.per_class[k]);
    const nlohmann::ordered_json j = {{"micro", retrieval::to_json(e.micro)},
                                      {"macro", retrieval::to_json(e.macro)},
                                      {"classes", classes},
                                      {"precision", e.precision}};
    py::dict d = from_json(j);
    d["recall"] = e.recall;
    py::list skipped;
    for (const auto& c : e.skipped_classes) skipped.append(text(c));
    d["skipped_classes"] = skipped;
    const nlohmann::ordered_json micro = retrieval::to_json(e.micro);
    for (const auto& [k, v] : micro.items()) d[text(k)] = from_json(v);
    return d;
}

py::dict evaluate(const py::object& D, const py::object& labels) {
    Eigen::MatrixXd d;
    if (is_path(D)) {
        const std::string p = path_in(D);
        d = Call().run([&] { return io::read_distance_matrix(p); });
    } else {
        d = matrix_in(D, "D");
    }
    std::vector<std::string> l;
    if (is_path(labels)) {
        const std::string p = path_in(labels);
        for (const auto& row : Call().run([&] { return io::read_labels(p); })) l.push_back(row.label);
    } else {
        for (const py::handle& x : labels) l.push_back(py::str(x).cast<std::string>());
    }
    Call call;
    const retrieval::Evaluation e = call.run([&] { return retrieval::evaluate(d, l); });
    return evaluation_dict(e);
}

std::vector<std::string> method_list(const py::object& methods) {
    std::vector<std::string> out;
    auto split = [&](const std::string& s) {
        size_t b = 0;
        while (b <= s.size()) {
            const size_t e = std::min(s.find(',', b), s.size());
            if (e > b) out.push_back(s.substr(b, e - b));
            b = e + 1;
        }
    };
    if (py::isinstance<py::str>(methods))
        split(methods.cast<std::string>());
    else
        for (const py::handle& m : methods) split(py::str(m).cast<std::string>());
    if (out.empty()) throw InputError("methods is empty: name at least one method");
    return out;
}

py::dict retrieve(const py::object& dataset, const py::object& out, const py::object& methods,
                  const py::object& labels, int words, const std::string& codebook, long long codebook_sample,
                  int simplify, double noise, long long seed, const std::optional<std::string>& sift, bool repair,
                  int threads, const py::object& log, const py::object& progress) {
    // The ranges of `canonform retrieve`'s options.
    if (words < 1 || words > 1000000) throw InputError("words must be between 1 and 1000000, got " + std::to_string(words));
    if (codebook_sample < 0 || codebook_sample > 2000000000LL)
        throw InputError("codebook_sample must be between 0 and 2000000000, got " + std::to_string(codebook_sample));
    if (simplify < 0 || simplify > 100000000)
        throw InputError("simplify must be between 0 and 100000000, got " + std::to_string(simplify));
    if (!std::isfinite(noise) || noise < 0 || noise > 10)
        throw InputError("noise must be a finite number between 0 and 10, got " + py::repr(py::float_(noise)).cast<std::string>());
    if (seed < 0 || seed > 4294967295LL) throw InputError("seed must be between 0 and 4294967295, got " + std::to_string(seed));
    if (threads < 0 || threads > 1024) throw InputError("threads must be between 0 and 1024, got " + std::to_string(threads));
    if (!log.is_none() && !PyCallable_Check(log.ptr())) throw InputError("log must be a callable(line) or None");

    retrieval::ExperimentOptions o;
    o.dataset = path_in(dataset);
    o.out = path_in(out);
    o.labels = labels.is_none() ? o.dataset + "/labels.csv" : path_in(labels);
    o.words = words;
    o.codebook_training.sample = codebook_sample;
    if (codebook == "kmeans" || codebook == "lloyd" || codebook == "random")
        o.codebook_training.method = views::parse_codebook_method(codebook);
    else
        o.codebook = codebook;  // a codebook file for every method
    o.simplify = simplify;
    o.noise = noise;
    o.seed = static_cast<std::uint64_t>(seed);
    o.threads = threads;
    o.repair = repair;
    if (sift) o.views.sift.backend = views::parse_sift_backend(*sift);
    for (const std::string& m : method_list(methods)) {
        if (retrieval::is_fused_spec(m))
            o.fused.push_back(retrieval::parse_fused_spec(m));
        else
            o.methods.push_back(canonical::parse_method_spec(m));
    }

    Call call(progress);
    const ProgressFn report = call.progress(), interrupt = call.interrupt_only();
    const bool with_progress = !progress.is_none();
    o.progress = [report, interrupt, with_progress](const std::string& method) -> ProgressFn {
        return [=](double f, const char* stage) { return (with_progress ? report : interrupt)(f, (method + ": " + stage).c_str()); };
    };
    // Each log line (between stages, on the calling thread): Ctrl-C is looked at, then the callable
    // gets the line; either raising stops the run with that exception. The lambda is copied
    // without the GIL, so it holds no Python object, only a pointer to the argument.
    const auto log_cause = std::make_shared<std::exception_ptr>();
    o.log = [log_cause, log_fn = &log](const std::string& line) {
        {
            py::gil_scoped_acquire gil;
            try {
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                if (!log_fn->is_none()) (*log_fn)(text(line));
            } catch (...) {
                *log_cause = std::current_exception();
            }
        }
        if (*log_cause) throw Cancelled();
    };

    std::vector<retrieval::MethodOutcome> outcomes;
    std::size_t meshes = 0;
    try {
        call.run([&] {
            const retrieval::Experiment experiment(o);
            outcomes = experiment.run();
            meshes = experiment.models().size();
            io::write_file_atomic(o.out + "/report.md", retrieval::report_markdown(o, meshes, outcomes, ""));
        });
    } catch (const Cancelled&) {
        if (*log_cause) std::rethrow_exception(*log_cause);
        throw;
    }
    py::dict result;
    result["out"] = text(o.out);
    result["report"] = text(retrieval::report_markdown(o, meshes, outcomes, ""));
    py::dict per_method;
    for (const retrieval::MethodOutcome& m : outcomes) {
        py::dict d;
        d["folder"] = text(m.folder);
        d["meshes"] = m.meshes;
        d["failed"] = m.failed;
        d["cached"] = m.cached;
        if (m.no_measures.empty())
            d["measures"] = evaluation_dict(m.evaluation);
        else
            d["measures"] = py::none();
        d["no_measures"] = text(m.no_measures);
        d["pose_consistency"] = m.pose_consistency >= 0 ? py::object(py::float_(m.pose_consistency)) : py::none();
        d["pose_consistency_pairs"] = m.pose_consistency_pairs;
        d["forms_seconds"] = m.forms_seconds;
        d["codebook_seconds"] = m.codebook_seconds;
        d["distances_seconds"] = m.distances_seconds;
        per_method[text(m.name())] = d;
    }
    result["methods"] = per_method;
    return result;
}

py::array_t<float> read_distance_matrix(const py::object& path) {
    const std::string p = path_in(path);
    const Eigen::MatrixXd D = Call().run([&] { return io::read_distance_matrix(p); });
    return array_out(Eigen::MatrixXf(D.cast<float>()));
}

std::vector<std::tuple<py::str, py::str>> read_labels(const py::object& path) {
    const std::string p = path_in(path);
    std::vector<std::tuple<py::str, py::str>> out;
    for (const auto& row : Call().run([&] { return io::read_labels(p); })) out.emplace_back(text(row.path), text(row.label));
    return out;
}

}  // namespace

void bind_retrieval(py::module_& m) {
    m.def("evaluate", &evaluate, py::arg("D"), py::arg("labels"),
          R"(The retrieval measures of a distance matrix (`canonform evaluate --json`),
psbTable's definitions (normalised by C-1).

D: a float (N, N) array or a distance-matrix file (float32 binary or .csv);
labels: N class names (any sequence; str() of each) or a labels file
(path,class rows). Returns a dict: micro and macro ({nn, first_tier,
second_tier, e_measure, dcg, queries}), classes ({class: measures}), precision
and recall (20 points: the averaged precision-recall curve), skipped_classes
(two models or fewer), and the five micro measures and queries again at the
top (d["nn"], ...).)");
    m.def("retrieve", &retrieve, py::arg("dataset"), py::arg("out"),
          py::arg("methods") = std::vector<std::string>{"none", "euclidean-N"}, py::kw_only(),
          py::arg("labels") = py::none(), py::arg("words") = 1500, py::arg("codebook") = "kmeans",
          py::arg("codebook_sample") = views::kDefaultCodebookSample, py::arg("simplify") = 0, py::arg("noise") = 0.0,
          py::arg("seed") = 0, py::arg("sift") = py::none(), py::arg("repair") = false, py::arg("threads") = 0,
          py::arg("log") = py::none(), py::arg("progress") = py::none(),
          R"(A retrieval experiment over a labelled collection, as `canonform retrieve` runs it:
per method, canonical forms, 66 views and SIFT per mesh (in parallel, cached in
OUT/cache), a codebook, histograms, clock-matching distances and the measures.
Writes the run folder `out` as the tool does (METHOD/distances.bin,
metrics.json, pr.csv, report.md, ...; no pictures) and reuses its cache.

dataset: the collection folder; labels: its labels file (default
DATASET/labels.csv); methods: a list of method specs ("euclidean-N:beta=65",
"fused:none+euclidean-N") or one comma-separated string; words, codebook
("kmeans", "lloyd", "random" or a codebook file), codebook_sample, simplify,
noise, seed, sift, repair, threads: the tool's options of the same names.
log: None or callable(line) for the tool's log lines; progress:
callable(fraction, stage). Ctrl-C stops the run (between meshes); a second
run continues from the cache.

Returns {"out", "report" (report.md's markdown), "methods": {FOLDER: {folder,
meshes, failed, cached, measures (as evaluate(), or None), no_measures,
pose_consistency (None if not measured), pose_consistency_pairs,
forms_seconds, codebook_seconds, distances_seconds}}}.)");
    m.def("read_distance_matrix", &read_distance_matrix, py::arg("path"),
          "Reads a distance-matrix file (float32 binary, or .csv): float32 (N, N).");
    m.def("read_labels", &read_labels, py::arg("path"),
          "Reads a labels file: a list of (path, class) tuples in file order.");
}

}  // namespace canonform::python
