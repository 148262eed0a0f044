// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/sharded_run.h"

#include "canonform/common/elapsed.h"
#include "canonform/common/parallel.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/views/view_directions.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace canonform::retrieval {

namespace {

using Json = nlohmann::ordered_json;

const Stage kStages[] = {Stage::Features, Stage::Codebook,  Stage::Histograms,
                         Stage::Index,    Stage::Distances, Stage::Merge};

Json read_json(const std::string& path) {
    const std::string bytes = io::read_file(path);
    try {
        return Json::parse(bytes);
    } catch (const std::exception& e) {
        throw InputError("'" + path + "': not valid JSON (" + e.what() + ")");
    }
}

void write_json(const std::string& path, const Json& j) {
    io::write_file_atomic(path, j.dump(1, ' ', false, Json::error_handler_t::replace) + "\n");
}

Json plan_json(const ShardedPlan& p) {
    const ExperimentOptions& o = p.experiment;
    Json methods = Json::array();
    for (const canonical::MethodSpec& m : o.methods) methods.push_back(m.to_string());
    Json j = {{"format", "canonform sharded run 1"},
              {"dataset", o.dataset},
              {"labels", o.labels},
              {"methods", methods},
              {"words", o.words},
              {"codebook", o.codebook},
              {"codebook_training",
               {{"method", views::codebook_method_name(o.codebook_training.method)},
                {"sample", o.codebook_training.sample},
                {"iterations", o.codebook_training.kmeans_iterations}}},
              {"sift", views::sift_backend_name(o.views.sift.backend)},
              {"simplify", o.simplify},
              {"noise", o.noise},
              {"seed", o.seed},
              {"repair", o.repair},
              {"shards", p.shards},
              {"blocks", p.blocks > 0 ? p.blocks : p.shards}};
    if (p.evaluation != "matrix") {  // absent for a matrix run: the plans of earlier runs stay equal
        j["evaluation"] = p.evaluation;
        j["neighbours"] = p.neighbours;
        j["exact"] = p.exact;
    }
    return j;
}

ShardedPlan plan_from_json(const Json& j, const std::string& run) {
    ShardedPlan p;
    ExperimentOptions& o = p.experiment;
    o.dataset = j.at("dataset").get<std::string>();
    o.labels = j.at("labels").get<std::string>();
    o.out = run;
    for (const auto& m : j.at("methods"))
        o.methods.push_back(canonical::parse_method_spec(m.get<std::string>()));
    o.words = j.at("words").get<int>();
    o.codebook = j.at("codebook").get<std::string>();
    const Json& training = j.at("codebook_training");
    o.codebook_training.method = views::parse_codebook_method(training.at("method").get<std::string>());
    o.codebook_training.sample = training.at("sample").get<std::int64_t>();
    o.codebook_training.kmeans_iterations = training.at("iterations").get<int>();
    o.views.sift.backend = views::parse_sift_backend(j.at("sift").get<std::string>());
    o.simplify = j.at("simplify").get<int>();
    o.noise = j.at("noise").get<double>();
    o.seed = j.at("seed").get<std::uint64_t>();
    o.repair = j.at("repair").get<bool>();
    p.shards = j.at("shards").get<int>();
    p.blocks = j.at("blocks").get<int>();
    if (j.contains("evaluation")) {
        p.evaluation = j.at("evaluation").get<std::string>();
        p.neighbours = j.at("neighbours").get<int>();
        p.exact = j.at("exact").get<bool>();
    }
    return p;
}

std::vector<Model> models_from_json(const Json& j) {
    std::vector<Model> models;
    for (const auto& e : j) {
        Model m;
        m.path = e.at("path").get<std::string>();
        m.label = e.at("class").get<std::string>();
        m.name = e.at("name").get<std::string>();
        m.hash = std::stoull(e.at("hash").get<std::string>(), nullptr, 16);
        m.error = e.at("error").get<std::string>();
        models.push_back(m);
    }
    return models;
}

ShardedPlan read_plan(const std::string& run) {
    const std::string path = run + "/sharded.json";
    if (!io::is_file(path))
        throw InputError("'" + run +
                         "' is not a sharded run (no sharded.json): start one with `canonform stage init`");
    try {
        return plan_from_json(read_json(path), run);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError("'" + path + "': " + e.what());
    }
}

std::vector<Model> read_models(const std::string& run) {
    const std::string path = run + "/models.json";
    try {
        return models_from_json(read_json(path));
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError("'" + path + "': " + e.what());
    }
}

std::string relative(const std::string& run, const std::string& path) {
    return path.compare(0, run.size() + 1, run + "/") == 0 ? path.substr(run.size() + 1) : path;
}

std::string parts_list(const std::vector<int>& v) {
    std::string s;
    for (int i : v) s += (s.empty() ? "" : ",") + std::to_string(i);
    return s;
}

}  // namespace

const char* stage_name(Stage s) {
    switch (s) {
        case Stage::Features:
            return "features";
        case Stage::Codebook:
            return "codebook";
        case Stage::Histograms:
            return "histograms";
        case Stage::Index:
            return "index";
        case Stage::Distances:
            return "distances";
        case Stage::Merge:
            return "merge";
    }
    return "?";
}

Stage parse_stage(const std::string& name) {
    for (Stage s : kStages)
        if (name == stage_name(s)) return s;
    throw InputError("unknown stage '" + name +
                     "' (features, codebook, histograms, index, distances, merge)");
}

void init_sharded_run(const ShardedPlan& plan) {
    const ExperimentOptions& o = plan.experiment;
    if (plan.shards < 1) throw InputError("--shards must be at least 1");
    if (plan.blocks < 0) throw InputError("--blocks must be at least 0");
    if (plan.evaluation != "matrix" && plan.evaluation != "neighbours")
        throw InputError("--evaluation " + plan.evaluation + ": matrix or neighbours");
    if (plan.neighbours < 0) throw InputError("--neighbours must be at least 0");
    io::make_directories(o.out + "/stages");
    const Json wanted = plan_json(plan);
    const std::string path = o.out + "/sharded.json";
    if (io::is_file(path)) {
        if (read_json(path) != wanted)
            throw InputError("'" + o.out + "' already holds a sharded run of another plan (" + path +
                             "): start another run folder");
        if (io::is_file(o.out + "/models.json")) return;
    }
    // The Experiment checks the collection (at least three meshes, distinct names, ...).
    const Experiment e(o);
    Json models = Json::array();
    for (const Model& m : e.models())
        models.push_back({{"path", m.path},
                          {"class", m.label},
                          {"name", m.name},
                          {"hash", io::hex(m.hash)},
                          {"error", m.error}});
    write_json(o.out + "/models.json", models);
    write_json(path, wanted);
}

ShardedRun::ShardedRun(const std::string& run, int threads, std::function<void(const std::string&)> log)
    : run_(run),
      plan_(read_plan(run)),
      experiment_([&] {
          ExperimentOptions o = plan_.experiment;
          o.threads = threads;
          o.log = log;
          return Experiment(o, read_models(run));
      }()),
      log_(std::move(log)) {
    plan_.experiment.threads = threads;
}

int ShardedRun::parts(Stage s) const {
    if (s == Stage::Features || s == Stage::Histograms) return plan_.shards;
    if (s == Stage::Distances) return plan_.blocks > 0 ? plan_.blocks : plan_.shards;
    if (s == Stage::Index) return by_neighbours() ? 1 : 0;
    return 1;
}

std::string ShardedRun::marker(Stage s, int index) const {
    return run_ + "/stages/" + stage_name(s) + "_" + std::to_string(index);
}

bool ShardedRun::done(Stage s, int index) const {
    const std::string path = marker(s, index) + ".json";
    if (!io::is_file(path)) return false;
    try {
        const Json m = read_json(path);
        for (const auto& f : m.at("outputs"))
            if (!io::is_file(run_ + "/" + f.get<std::string>())) return false;
        return true;
    } catch (const std::exception&) {
        return false;  // a marker that cannot be read: the stage is redone
    }
}

std::pair<std::size_t, std::size_t> ShardedRun::shard_models(int shard) const {
    const std::size_t n = experiment_.models().size(), s = static_cast<std::size_t>(plan_.shards);
    const auto i = static_cast<std::size_t>(shard);
    return {i * n / s, (i + 1) * n / s};
}

std::pair<std::size_t, std::size_t> ShardedRun::block_rows(int block, std::size_t n) const {
    // Row r holds n - 1 - r pairs; block b starts at the first row with b/B of the pairs before it.
    const auto blocks = static_cast<std::size_t>(parts(Stage::Distances));
    const double total = 0.5 * static_cast<double>(n) * static_cast<double>(n > 0 ? n - 1 : 0);
    auto start = [&](std::size_t b) {
        if (b == 0) return std::size_t{0};
        if (b >= blocks) return n;
        const double want = total * static_cast<double>(b) / static_cast<double>(blocks);
        std::size_t r = 0;
        double before = 0;
        while (r < n && before < want) before += static_cast<double>(n - 1 - r++);
        return r;
    };
    const auto b = static_cast<std::size_t>(block);
    return {start(b), start(b + 1)};
}

bool ShardedRun::run(Stage s, int index) const {
    if (parts(s) == 0)
        throw InputError(std::string("stage ") + stage_name(s) +
                         " is part of a run with --evaluation neighbours only");
    if (index < 0 || index >= parts(s))
        throw InputError(std::string("stage ") + stage_name(s) + " has parts 0 to " +
                         std::to_string(parts(s) - 1) + ", not " + std::to_string(index));
    if (done(s, index)) return false;
    // What the stage needs first: every part of the stage before it (that the run has).
    int at = static_cast<int>(s) - 1;
    while (at > 0 && parts(kStages[at]) == 0) --at;
    if (s != Stage::Features) {
        const Stage before = kStages[at];
        std::vector<int> missing;
        for (int i = 0; i < parts(before); ++i)
            if (!done(before, i)) missing.push_back(i);
        if (!missing.empty())
            throw InputError(std::string("stage ") + stage_name(s) + " needs the " + stage_name(before) +
                             " parts " + parts_list(missing) + " first");
    }
    const std::string failed = marker(s, index) + ".failed";
    io::make_directories(run_ + "/stages");
    const auto t0 = SteadyClock::now();
    Json m;
    m["stage"] = stage_name(s);
    m["index"] = index;
    m["outputs"] = Json::array();
    try {
        switch (s) {
            case Stage::Features:
                features(index, m);
                break;
            case Stage::Codebook:
                codebook(m);
                break;
            case Stage::Histograms:
                histograms(index, m);
                break;
            case Stage::Index:
                this->index(m);
                break;
            case Stage::Distances:
                by_neighbours() ? neighbours(index, m) : distances(index, m);
                break;
            case Stage::Merge:
                merge(m);
                break;
        }
        m["seconds"] = seconds_since(t0);
        write_json(marker(s, index) + ".json", m);
    } catch (const std::exception& e) {
        io::write_file_atomic(failed, std::string(e.what()) + "\n");
        throw;
    }
    std::error_code ec;
    std::filesystem::remove(io::fs_path(failed), ec);
    if (log_) {
        char line[200];
        std::snprintf(line, sizeof line, "[%s %d/%d] done in %.1f s", stage_name(s), index, parts(s),
                      m["seconds"].get<double>());
        log_(line);
    }
    return true;
}

void ShardedRun::run_all() const {
    for (Stage s : kStages)
        for (int i = 0; i < parts(s); ++i) run(s, i);
}

std::vector<StageStatus> ShardedRun::status() const {
    std::vector<StageStatus> out;
    for (Stage s : kStages) {
        if (parts(s) == 0) continue;
        StageStatus st;
        st.stage = s;
        st.parts = parts(s);
        for (int i = 0; i < st.parts; ++i) {
            if (done(s, i)) {
                st.done.push_back(i);
                try {
                    st.seconds += read_json(marker(s, i) + ".json").at("seconds").get<double>();
                } catch (const std::exception&) {
                }
            } else if (io::is_file(marker(s, i) + ".failed")) {
                st.failed.push_back(i);
                std::string msg = io::read_file(marker(s, i) + ".failed");
                while (!msg.empty() && msg.back() == '\n') msg.pop_back();
                st.errors.push_back(msg);
            } else {
                st.pending.push_back(i);
            }
        }
        out.push_back(st);
    }
    return out;
}

void ShardedRun::features(int shard, Json& m) const {
    // Plain variables, not a structured binding: clang 14 cannot capture one in a lambda.
    const auto models = shard_models(shard);
    const std::size_t begin = models.first, end = models.second;
    Json methods = Json::object();
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        io::make_directories(run_ + "/" + spec.folder() + "/forms");
        std::vector<MeshFeatures> r(end - begin);
        ParallelOptions par;
        par.threads = plan_.experiment.threads;
        const auto t0 = SteadyClock::now();
        parallel_for(
            static_cast<std::ptrdiff_t>(end - begin),
            [&](std::ptrdiff_t k, int) {
                r[static_cast<std::size_t>(k)] =
                    experiment_.mesh_features(spec, begin + static_cast<std::size_t>(k));
            },
            par);
        Json meshes = Json::array();
        for (std::size_t k = begin; k < end; ++k) {
            const MeshFeatures& f = r[k - begin];
            const std::size_t rows = views::feature_rows(f.features);
            meshes.push_back({{"model", k},
                              {"ok", f.ok},
                              {"cached", f.cached},
                              {"rows", rows},
                              {"error", f.error},
                              {"note", f.note}});
            if (f.ok) {
                const std::string key = experiment_.cache_entry(spec, k);
                for (const std::string& p :
                     {key + ".cfvd", key + ".ply",
                      run_ + "/" + spec.folder() + "/forms/" + experiment_.models()[k].name + ".ply"})
                    m["outputs"].push_back(relative(run_, p));
            }
        }
        methods[spec.folder()] = {{"meshes", meshes}, {"seconds", seconds_since(t0)}};
    }
    m["methods"] = methods;
}

ShardedRun::Collected ShardedRun::collect(const canonical::MethodSpec& spec) const {
    Collected c;
    for (int i = 0; i < parts(Stage::Features); ++i) {
        const Json m = read_json(marker(Stage::Features, i) + ".json");
        const Json& mj = m.at("methods").at(spec.folder());
        c.seconds += mj.at("seconds").get<double>();
        for (const auto& e : mj.at("meshes")) {
            const auto k = e.at("model").get<std::size_t>();
            const std::string& name = experiment_.models().at(k).name;
            if (!e.at("note").get<std::string>().empty())
                c.notes.push_back("[" + spec.folder() + "] " + name + ": " + e.at("note").get<std::string>());
            if (e.at("ok").get<bool>()) {
                c.good.push_back(k);
                c.rows.push_back(e.at("rows").get<std::size_t>());
                c.cached += e.at("cached").get<bool>();
            } else {
                c.failures += name + ": " + e.at("error").get<std::string>() + "\n";
            }
        }
    }
    return c;
}

void ShardedRun::codebook(Json& m) const {
    const ExperimentOptions& o = plan_.experiment;
    for (const canonical::MethodSpec& spec : o.methods) {
        const std::string dir = run_ + "/" + spec.folder();
        io::make_directories(dir);
        const Collected c = collect(spec);
        if (c.good.size() < 3)
            throw InputError(spec.folder() +
                             ": fewer than three meshes succeeded; see the features markers in " + run_ +
                             "/stages");
        views::Codebook cb;
        if (!o.codebook.empty()) {
            cb = views::Codebook::load(o.codebook);
        } else {
            // The training of Experiment::codebook() (the good meshes' descriptors stacked in
            // collection order, the same options), holding only the rows it trains on: read mesh by
            // mesh from the cache (views::stacked_rows()).
            const views::CodebookOptions co = experiment_.codebook_options();
            std::int64_t total = 0;
            for (std::size_t r : c.rows) total += static_cast<std::int64_t>(r);
            MeshFeatures f;
            const views::SiftDescriptors training = views::stacked_rows(
                c.rows, views::Codebook::training_rows(total, co),
                [&](std::size_t g) -> const std::vector<views::SiftDescriptors>& {
                    f = experiment_.mesh_features(spec, c.good[g]);
                    if (!f.ok) throw InputError(experiment_.models()[c.good[g]].name + ": " + f.error);
                    if (views::feature_rows(f.features) != c.rows[g])
                        throw InputError(spec.folder() +
                                         ": the cached features changed since the features stage");
                    return f.features;
                });
            cb = views::Codebook::train_on_rows(training, total, co);
        }
        cb.save(dir + "/codebook.bin");
        m["outputs"].push_back(relative(run_, dir + "/codebook.bin"));
    }
}

void ShardedRun::histograms(int shard, Json& m) const {
    // Plain variables, not a structured binding: clang 14 cannot capture one in a lambda.
    const auto models = shard_models(shard);
    const std::size_t begin = models.first, end = models.second;
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        const std::string dir = run_ + "/" + spec.folder();
        io::make_directories(dir + "/descriptors");
        const views::Codebook cb = views::Codebook::load(dir + "/codebook.bin");
        const Collected c = collect(spec);
        std::vector<std::size_t> mine;
        for (std::size_t k : c.good)
            if (k >= begin && k < end) mine.push_back(k);
        ParallelOptions par;
        par.threads = plan_.experiment.threads;
        parallel_for(
            static_cast<std::ptrdiff_t>(mine.size()),
            [&](std::ptrdiff_t i, int) {
                const std::size_t k = mine[static_cast<std::size_t>(i)];
                const Model& model = experiment_.models()[k];
                const MeshFeatures f = experiment_.mesh_features(spec, k);
                if (!f.ok) throw InputError(model.name + ": " + f.error);
                views::write_descriptor(dir + "/descriptors/" + model.name + ".cfvd",
                                        views::make_descriptor(f.features, &cb, model.path));
            },
            par);
        for (std::size_t k : mine)
            m["outputs"].push_back(
                relative(run_, dir + "/descriptors/" + experiment_.models()[k].name + ".cfvd"));
    }
}

void ShardedRun::distances(int block, Json& m) const {
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        const std::string dir = run_ + "/" + spec.folder();
        const Collected c = collect(spec);
        const auto rows = block_rows(block, c.good.size());
        const auto r0 = rows.first, r1 = rows.second;
        std::vector<std::vector<views::Histogram>> hist(c.good.size());
        ParallelOptions par;
        par.threads = plan_.experiment.threads;
        parallel_for(
            static_cast<std::ptrdiff_t>(c.good.size()),
            [&](std::ptrdiff_t i, int) {
                const std::string& name = experiment_.models()[c.good[static_cast<std::size_t>(i)]].name;
                hist[static_cast<std::size_t>(i)] =
                    views::read_descriptor(dir + "/descriptors/" + name + ".cfvd").histograms;
            },
            par);
        const Eigen::MatrixXf B =
            views::distance_rows(hist, views::rotation_view_maps(), r0, r1, plan_.experiment.threads);
        // Row-major float32 rows r0..r1-1, every column.
        const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> R = B;
        const std::string path = dir + "/stages/distances_" + std::to_string(block) + ".bin";
        io::make_directories(dir + "/stages");
        io::write_file_atomic(path, std::string(reinterpret_cast<const char*>(R.data()),
                                                static_cast<std::size_t>(R.size()) * sizeof(float)));
        m["outputs"].push_back(relative(run_, path));
        m["rows"][spec.folder()] = {r0, r1};
    }
}

void ShardedRun::merge(Json& m) const {
    std::vector<MethodOutcome> outcomes;
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        const std::string dir = run_ + "/" + spec.folder();
        const Collected c = collect(spec);
        for (const std::string& note : c.notes)
            if (log_) log_(note);
        const std::size_t n = c.good.size();
        io::write_file_atomic(dir + "/failures.txt", c.failures);
        MethodOutcome out;
        out.spec = spec;
        out.folder = dir;
        out.meshes = n;
        out.failed = experiment_.models().size() - n;
        out.cached = c.cached;
        out.forms_seconds = c.seconds;
        out.codebook_seconds = read_json(marker(Stage::Codebook, 0) + ".json").at("seconds").get<double>();
        if (by_neighbours()) {
            for (Stage st : {Stage::Histograms, Stage::Index, Stage::Distances})
                for (int s = 0; s < parts(st); ++s)
                    out.distances_seconds += read_json(marker(st, s) + ".json").at("seconds").get<double>();
            merge_neighbours(spec, out, m);
            outcomes.push_back(out);
            continue;
        }
        Eigen::MatrixXf D = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
        double distance_seconds = 0;
        for (int b = 0; b < parts(Stage::Distances); ++b) {
            const auto rows = block_rows(b, n);
            const auto r0 = rows.first, r1 = rows.second;
            const std::string path = dir + "/stages/distances_" + std::to_string(b) + ".bin";
            const std::string bytes = io::read_file(path);
            if (bytes.size() != (r1 - r0) * n * sizeof(float))
                throw InputError("'" + path + "': " + std::to_string(bytes.size()) + " bytes, expected " +
                                 std::to_string((r1 - r0) * n * sizeof(float)) + " (rows " +
                                 std::to_string(r0) + " to " + std::to_string(r1) + " of " +
                                 std::to_string(n) + ")");
            const float* f = reinterpret_cast<const float*>(bytes.data());
            for (std::size_t r = r0; r < r1; ++r)
                for (std::size_t col = r + 1; col < n; ++col) {
                    const float d = f[(r - r0) * n + col];
                    D(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(col)) = d;
                    D(static_cast<Eigen::Index>(col), static_cast<Eigen::Index>(r)) = d;
                }
            distance_seconds += read_json(marker(Stage::Distances, b) + ".json").at("seconds").get<double>();
        }
        for (int s = 0; s < parts(Stage::Histograms); ++s)
            distance_seconds += read_json(marker(Stage::Histograms, s) + ".json").at("seconds").get<double>();
        out.distances_seconds = distance_seconds;
        experiment_.finish_method(out, c.good, D);
        for (const char* f : {"/distances.bin", "/distances.csv", "/models.csv", "/metrics.json",
                              "/timings.json", "/pr.csv", "/failures.txt"})
            m["outputs"].push_back(relative(run_, dir + f));
        outcomes.push_back(out);
    }
    ExperimentOptions o = plan_.experiment;
    io::write_file_atomic(run_ + "/report.md",
                          report_markdown(o, experiment_.models().size(), outcomes,
                                          "\n(A sharded run: timings are CPU seconds summed over "
                                          "the stages' parts.)\n"));
    m["outputs"].push_back("report.md");
}

}  // namespace canonform::retrieval
