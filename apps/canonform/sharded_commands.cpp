// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: a retrieval run beyond one machine - stage (one stage, one shard) and status.
#include "cli.h"

#include "canonform/io/files.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/retrieval/sharded_run.h"
#include "canonform/surface/simplify.h"
#include "canonform/views/view_descriptor.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace canonform::cli {

namespace {

std::string join(const std::vector<int>& v) {
    std::string s;
    for (int i : v) s += (s.empty() ? "" : ",") + std::to_string(i);
    return s.empty() ? "-" : s;
}

/// What the commands that start a sharded run (stage init, slurm) parse: retrieve's options and the shards.
struct PlanArgs {
    retrieval::ShardedPlan plan;
    ExperimentArgs ex;
};

/// The options of a sharded run's plan (stage init, slurm): retrieve's, and the shards.
void add_plan_options(CLI::App* c, PlanArgs& a) {
    add_experiment_options(c, a.ex);
    c->add_option("--shards", a.plan.shards, "mesh shards")->check(CLI::Range(1, 1000000));
    c->add_option("--blocks", a.plan.blocks, "row blocks of the distance matrix (0: as many as shards)")
        ->check(CLI::Range(0, 1000000));
    c->add_option(
         "--evaluation", a.plan.evaluation,
         "matrix (the N x N distance matrix) or neighbours (each model's K nearest through the collection "
         "index: no matrix, for collections too large for one; NN, tiers and E-measure exact, DCG truncated "
         "at K)")
        ->check(CLI::IsMember({"matrix", "neighbours"}));
    c->add_option("--neighbours", a.plan.neighbours,
                  "K of --evaluation neighbours (0: max(2 x largest class, 32))")
        ->check(CLI::Range(0, 1000000));
    c->add_flag("--exact-neighbours", a.plan.exact,
                "--evaluation neighbours by exhaustive clock matching even above the two-stage size");
}

/// init_sharded_run() of the parsed plan (absolute run folder and dataset: jobs run elsewhere).
retrieval::ShardedPlan start_run(const PlanArgs& parsed) {
    retrieval::ShardedPlan p = parsed.plan;
    ExperimentArgs absolute = parsed.ex;
    auto& a = absolute.o;
    const auto absolute_path = [](const std::string& given) {
        return io::utf8_path(std::filesystem::absolute(io::fs_path(given)).lexically_normal());
    };
    a.dataset = absolute_path(a.dataset);
    a.out = absolute_path(a.out);
    const auto separator = [](char c) { return c == '/' || c == std::filesystem::path::preferred_separator; };
    while (a.out.size() > 1 && separator(a.out.back())) a.out.pop_back();
    while (a.dataset.size() > 1 && separator(a.dataset.back())) a.dataset.pop_back();
    if (!a.labels.empty()) a.labels = absolute_path(a.labels);
    p.experiment = finish_experiment_options(absolute, false);
    auto& o = p.experiment;
    if (!o.codebook.empty()) o.codebook = absolute_path(o.codebook);
    o.log = [](const std::string& line) { std::cerr << line << "\n"; };
    retrieval::init_sharded_run(p);
    return p;
}

}  // namespace

void add_stage(CLI::App& app) {
    struct Args : PlanArgs {
        std::string run, stage;
        int shard = -1, threads = 0;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand(
        "stage",
        "one stage of a sharded retrieval run (state in the run folder, every stage resumable): init, "
        "features, codebook, histograms, index (--evaluation neighbours), distances, merge, or all");
    c->require_subcommand(1);

    auto* init = c->add_subcommand("init", "start a sharded run: the plan and the collection, read once");
    add_plan_options(init, *a);
    init->callback([a] {
        const retrieval::ShardedPlan p = start_run(*a);
        std::cerr << "stage init: " << p.experiment.out << " (" << p.shards << " shards)\n";
    });

    for (const char* name : {"features", "codebook", "histograms", "index", "distances", "merge", "all"}) {
        const std::string n = name;
        const bool sharded = n == "features" || n == "histograms" || n == "distances";
        auto* s = c->add_subcommand(n, n == "all" ? "every stage of the run, here, skipping what is done"
                                                  : "the " + n + " stage" + (sharded ? " of one part" : ""));
        s->add_option("RUN", a->run, "the run folder (`canonform stage init`)")->required();
        if (sharded)
            s->add_option("--shard", a->shard,
                          n == "distances" ? "the row block (0-based)" : "the shard (0-based)")
                ->required()
                ->check(CLI::Range(0, 1000000));
        s->add_option("--threads", a->threads, "meshes or rows in parallel (0: every core)")
            ->check(CLI::Range(0, 1024));
        s->callback([a, n] {
            const retrieval::ShardedRun r(a->run, a->threads,
                                          [](const std::string& line) { std::cerr << line << "\n"; });
            if (n == "all") {
                r.run_all();
                return;
            }
            const retrieval::Stage st = retrieval::parse_stage(n);
            if (!r.run(st, std::max(a->shard, 0)))
                std::cerr << "stage " << n << " " << std::max(a->shard, 0) << ": already done\n";
        });
    }
}

void add_status(CLI::App& app) {
    struct Args {
        std::string run;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("status",
                                 "where a sharded run stands: per stage the parts done, failed and "
                                 "pending, and an estimate of the work left");
    c->add_option("RUN", a->run, "the run folder")->required();
    c->add_flag("--json", a->json, "print the status as JSON");
    c->callback([a] {
        const retrieval::ShardedRun r(a->run);
        const auto st = r.status();
        // Work left: the pending and failed parts of a stage at the mean time of its done parts;
        // a stage with none done yet is not estimated.
        double left = 0;
        std::vector<std::string> unknown;
        nlohmann::ordered_json stages = nlohmann::ordered_json::array();
        for (const auto& s : st) {
            const std::size_t todo = s.pending.size() + s.failed.size();
            double est = -1;
            if (todo && !s.done.empty())
                est = s.seconds / static_cast<double>(s.done.size()) * static_cast<double>(todo);
            if (todo && s.done.empty()) unknown.push_back(retrieval::stage_name(s.stage));
            if (est > 0) left += est;
            stages.push_back({{"stage", retrieval::stage_name(s.stage)},
                              {"parts", s.parts},
                              {"done", s.done},
                              {"failed", s.failed},
                              {"pending", s.pending},
                              {"errors", s.errors},
                              {"seconds", s.seconds}});
        }
        bool complete = true;
        for (const auto& s : st) complete = complete && s.done.size() == static_cast<std::size_t>(s.parts);
        if (a->json) {
            print_json({{"run", a->run},
                        {"complete", complete},
                        {"stages", stages},
                        {"seconds_left", left},
                        {"not_estimated", unknown}});
            return;
        }
        std::cout << "| stage | parts | done | failed | pending | seconds |\n|---|---|---|---|---|---|\n";
        for (const auto& s : st) {
            char sec[32];
            std::snprintf(sec, sizeof sec, "%.1f", s.seconds);
            std::cout << "| " << retrieval::stage_name(s.stage) << " | " << s.parts << " | " << s.done.size()
                      << " | " << join(s.failed) << " | " << join(s.pending) << " | " << sec << " |\n";
        }
        for (const auto& s : st)
            for (std::size_t k = 0; k < s.failed.size(); ++k)
                std::cout << "failed: " << retrieval::stage_name(s.stage) << " " << s.failed[k] << ": "
                          << s.errors[k] << "\n";
        if (complete) {
            std::cout << "complete\n";
            return;
        }
        char line[200];
        std::snprintf(line, sizeof line, "work left: about %.0f CPU-s of estimated stages", left);
        std::cout << line;
        if (!unknown.empty()) {
            std::cout << " (not estimated yet:";
            for (const auto& u : unknown) std::cout << " " << u;
            std::cout << ")";
        }
        std::cout << "\n";
    });
}

namespace {

/// `text` in single quotes for bash.
std::string quoted(const std::string& text) {
    std::string q = "'";
    for (char ch : text) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
}

/// What `canonform slurm` asks of the scheduler.
struct SlurmOptions {
    std::string partition, time = "01:00:00", mem, account, canonform;
    int cpus = 1, max_parallel = 0;
    bool submit = false;
};

/// The batch script of one stage: a job array over its parts (or one job), running
/// `canonform stage STAGE RUN [--shard $SLURM_ARRAY_TASK_ID]` with the job's CPUs.
std::string sbatch_script(const retrieval::ShardedRun& run, retrieval::Stage stage, const SlurmOptions& s,
                          const std::string& exe) {
    const std::string name = retrieval::stage_name(stage);
    const std::string& dir = run.plan().experiment.out;
    const int parts = run.parts(stage);
    const bool array = stage == retrieval::Stage::Features || stage == retrieval::Stage::Histograms ||
                       stage == retrieval::Stage::Distances;
    std::ostringstream o;
    o << "#!/bin/bash\n# canonform: stage '" << name << "' of the sharded run " << dir
      << " (written by `canonform slurm`).\n"
      << "#SBATCH --job-name=cf-" << name << "\n";
    if (array)
        o << "#SBATCH --array=0-" << parts - 1
          << (s.max_parallel > 0 ? "%" + std::to_string(s.max_parallel) : "") << "\n";
    o << "#SBATCH --cpus-per-task=" << s.cpus << "\n#SBATCH --time=" << s.time << "\n";
    if (!s.partition.empty()) o << "#SBATCH --partition=" << s.partition << "\n";
    if (!s.mem.empty()) o << "#SBATCH --mem=" << s.mem << "\n";
    if (!s.account.empty()) o << "#SBATCH --account=" << s.account << "\n";
    o << "#SBATCH --output=" << dir << "/slurm/logs/" << name << (array ? "_%a" : "") << "_%j.out\n"
      << "#SBATCH --kill-on-invalid-dep=yes\n"
      << "set -eu\n"
      << "exec " << quoted(exe) << " stage " << name << " " << quoted(dir)
      << (array ? " --shard \"$SLURM_ARRAY_TASK_ID\"" : "") << " --threads \"${SLURM_CPUS_PER_TASK:-"
      << s.cpus << "}\"\n";
    return o.str();
}

/// Runs `command`, returns its standard output (UsageError-free: an Error naming it on failure).
std::string run_command(const std::string& command) {
#ifdef _WIN32
    throw std::runtime_error("cannot run '" + command +
                             "': Slurm's commands are Linux programs (use the Linux build)");
#else
    FILE* p = popen(command.c_str(), "r");
    if (!p) throw std::runtime_error("cannot run: " + command);
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    const int rc = pclose(p);
    if (rc != 0)
        throw std::runtime_error("'" + command + "' failed (exit status " + std::to_string(rc) + "): " + out);
    return out;
#endif
}

}  // namespace

void add_slurm(CLI::App& app) {
    struct Args : PlanArgs {
        SlurmOptions s;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand(
        "slurm",
        "a sharded retrieval run on a Slurm cluster: writes one sbatch script per stage (job arrays over the "
        "shards, each stage after the one before: afterok) into RUN/slurm/, and with --submit submits "
        "them; again after a failure, it submits only the parts not done");
    add_plan_options(c, *a);
    c->add_option("--partition", a->s.partition, "Slurm partition (default: the cluster's)");
    c->add_option("--time", a->s.time, "time limit of each job (Slurm's format)");
    c->add_option("--cpus-per-task", a->s.cpus, "CPUs of each job (its --threads)")
        ->check(CLI::Range(1, 1024));
    c->add_option("--mem", a->s.mem, "memory of each job (Slurm's format, e.g. 8G; default: the cluster's)");
    c->add_option("--account", a->s.account, "Slurm account");
    c->add_option("--max-parallel", a->s.max_parallel,
                  "at most this many parts of a stage at once (0: no limit)")
        ->check(CLI::Range(0, 1000000));
    c->add_option("--canonform", a->s.canonform, "the canonform executable on the nodes (default: this one)");
    c->add_flag("--submit", a->s.submit,
                "submit the scripts (sbatch --parsable), only the parts not done yet");
    c->callback([a] {
        const retrieval::ShardedPlan p = start_run(*a);
        const std::string& dir = p.experiment.out;
        const retrieval::ShardedRun run(dir);
        std::string exe = a->s.canonform;
#ifdef _WIN32
        if (exe.empty())
            throw UsageError(
                "slurm: a Slurm cluster runs the Linux build: name its canonform with --canonform");
#else
        if (exe.empty()) exe = std::filesystem::read_symlink("/proc/self/exe").string();
#endif
        io::make_directories(dir + "/slurm/logs");
        const retrieval::Stage stages[] = {retrieval::Stage::Features,   retrieval::Stage::Codebook,
                                           retrieval::Stage::Histograms, retrieval::Stage::Index,
                                           retrieval::Stage::Distances,  retrieval::Stage::Merge};
        std::string scripts;
        for (const auto st : stages) {
            if (run.parts(st) == 0) continue;  // the index stage of a matrix run
            const std::string name = std::string(retrieval::stage_name(st)) + ".sbatch";
            io::write_file_atomic(dir + "/slurm/" + name, sbatch_script(run, st, a->s, exe));
            scripts += " " + name;
        }
        if (!a->s.submit) {
            std::cout << dir << "/slurm/:" << scripts << " (submit with --submit)\n";
            return;
        }
        // Only what is not done: a stage whose parts are all done is left out, a job array covers
        // only the parts left; each job waits for the one before it (afterok).
        std::string previous;
        nlohmann::ordered_json jobs = nlohmann::ordered_json::array();
        for (const auto& s : run.status()) {
            std::vector<int> todo = s.pending;
            todo.insert(todo.end(), s.failed.begin(), s.failed.end());
            std::sort(todo.begin(), todo.end());
            if (todo.empty()) continue;
            const std::string name = retrieval::stage_name(s.stage);
            std::string cmd = "sbatch --parsable";
            if (s.parts > 1 || s.stage == retrieval::Stage::Features ||
                s.stage == retrieval::Stage::Histograms || s.stage == retrieval::Stage::Distances) {
                cmd += " --array=" + join(todo);
                if (a->s.max_parallel > 0) cmd += "%" + std::to_string(a->s.max_parallel);
            }
            if (!previous.empty()) cmd += " --dependency=afterok:" + previous;
            cmd += " " + quoted(dir + "/slurm/" + name + ".sbatch");
            std::string id = run_command(cmd + " 2>&1");
            id = id.substr(0, id.find_first_of(";\n"));
            if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
                throw std::runtime_error("sbatch gave no job id for stage " + name + ": " + id);
            previous = id;
            jobs.push_back({{"stage", name}, {"job", id}, {"parts", todo}});
            std::cout << name << " " << id << " " << join(todo) << "\n";
        }
        if (jobs.empty()) std::cout << "nothing to submit: the run is complete\n";
        io::write_file_atomic(dir + "/slurm/jobs.json", jobs.dump(1) + "\n");
    });
}

void add_index(CLI::App& app) {
    struct Args {
        std::string run, methods;
        int simplify = 0;
        CLI::Option* simplify_option = nullptr;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("index",
                                 "pack the histograms of a retrieval run for queries (METHOD/index.cfci, "
                                 "one per method): `canonform query` reads it");
    c->add_option("RUN", a->run, "a run folder (`canonform retrieve` or a sharded run, finished)")
        ->required();
    c->add_option("--method", a->methods,
                  "comma-separated methods, as the run's --method (default: a sharded "
                  "run's methods, else every method folder of the run)");
    a->simplify_option =
        c->add_option("--simplify", a->simplify,
                      "the run's --simplify, for the queries (default: a sharded run's, else 0)")
            ->check(CLI::Range(0, 100000000));
    c->callback([a] {
        std::vector<canonical::MethodSpec> methods;
        int simplify = a->simplify;
        if (io::is_file(a->run + "/sharded.json")) {
            const retrieval::ShardedRun r(a->run);
            methods = r.plan().experiment.methods;
            if (a->simplify_option->count() == 0) simplify = r.plan().experiment.simplify;
        }
        if (!a->methods.empty()) {
            methods.clear();
            for (const std::string& m : split_list(a->methods))
                methods.push_back(canonical::parse_method_spec(m));
        }
        if (methods.empty())
            for (const canonical::CanonicalMethod* m : canonical::canonical_methods()) {
                const canonical::MethodSpec spec = canonical::parse_method_spec(m->name);
                if (io::is_file(a->run + "/" + spec.folder() + "/models.csv")) methods.push_back(spec);
            }
        if (methods.empty())
            throw InputError("'" + a->run + "': no method folder with models.csv: name --method");
        for (const canonical::MethodSpec& m : methods) {
            const auto t0 = std::chrono::steady_clock::now();
            const std::string folder = a->run + "/" + m.folder();
            const retrieval::CollectionIndex x =
                retrieval::index_method_folder(folder, m.to_string(), simplify);
            x.save(folder + "/index.cfci");
            char line[300];
            std::snprintf(line, sizeof line,
                          "index: %s/index.cfci: %zu models, %.1f MiB of histograms, %.1f MiB of first-pass "
                          "codes, %.2f s\n",
                          folder.c_str(), x.size(), static_cast<double>(x.bytes()) / (1 << 20),
                          static_cast<double>(x.first_pass().bytes()) / (1 << 20), seconds_since(t0));
            std::cerr << line;
        }
    });
}

void add_query(CLI::App& app) {
    struct Args {
        std::string run, method;
        std::vector<std::string> meshes;
        std::size_t top = 10, candidates = 0;
        int threads = 0;
        bool json = false, repair = false, exact = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("query",
                                 "the K nearest models of an indexed run (`canonform index`) to each mesh: "
                                 "only the query's form and descriptor are computed; above " +
                                     std::to_string(retrieval::CollectionIndex::kTwoStageAbove) +
                                     " models in two stages (a first pass proposes candidates, clock "
                                     "matching ranks them: exact distances, recall in docs/scale.md)");
    c->add_option("RUN", a->run, "an indexed run folder")->required();
    c->add_option("MESH", a->meshes, "query meshes")->required();
    c->add_option("--top", a->top, "K: models per query")->check(CLI::Range(1, 100000000));
    c->add_option("--method", a->method, "the method folder to search (default: the run's only index)");
    c->add_option("--threads", a->threads, "models scored in parallel (0: every core)")
        ->check(CLI::Range(0, 1024));
    c->add_flag("--json", a->json, "print the answers as JSON");
    c->add_flag("--exact", a->exact, "exhaustive clock matching over every model (no first pass)");
    c->add_option("--candidates", a->candidates,
                  "first-pass candidates that clock matching ranks (0: automatic, " +
                      retrieval::CollectionIndex::default_candidates_rule() +
                      " for N models; a number uses the first pass at any size)")
        ->check(CLI::Range(0, 100000000));
    add_repair_flag(c, a->repair);
    c->callback([a] {
        std::string folder = a->method;
        if (folder.empty()) {
            std::vector<std::string> found;
            for (const auto& e : std::filesystem::directory_iterator(io::fs_path(a->run)))
                if (io::is_file(io::utf8_path(e.path()) + "/index.cfci"))
                    found.push_back(io::utf8_path(e.path().filename()));
            if (found.size() != 1)
                throw InputError("'" + a->run + "': " + std::to_string(found.size()) +
                                 " method folders have an index.cfci: name one with --method (run `canonform "
                                 "index` first)");
            folder = found[0];
        }
        // Mapped: a query reads only the models it scores.
        const retrieval::CollectionIndex x =
            retrieval::CollectionIndex::load(a->run + "/" + folder + "/index.cfci", true);
        const canonical::MethodSpec spec = canonical::parse_method_spec(x.method());
        if (!x.first_pass().trained() && !a->exact &&
            (a->candidates > 0 || x.size() > retrieval::CollectionIndex::kTwoStageAbove))
            std::cerr
                << "canonform query: the index has no first pass (written by an older canonform): exhaustive "
                   "search; run `canonform index` again for two-stage queries\n";
        if (a->top > x.size())  // said, not silent: fewer answers than asked for
            std::cerr << "canonform query: --top " << a->top << " is more than the " << x.size()
                      << " models of the index: all " << x.size() << " are listed\n";
        nlohmann::ordered_json all = nlohmann::ordered_json::array();
        for (const std::string& path : a->meshes) {
            const auto t0 = std::chrono::steady_clock::now();
            Mesh m = read_input_mesh(path, a->repair, true, false);
            if (x.simplify() > 0 && m.V.rows() > x.simplify()) m = surface::simplify_mesh(m, x.simplify());
            canonical::MethodContext context;
            context.threads = a->threads;
            const Eigen::MatrixXd X =
                on_input(path, [&] { return spec.method().run(m.V, m.F, spec.settings(), context).V; });
            const views::ViewSet vs = on_input(path, [&] {
                views::ViewDescriptorOptions vo;
                vo.keep_images = false;
                return views::compute_views(X, m.F, vo);
            });
            const auto hist = views::view_histograms(vs.features, x.codebook());
            const double describe = seconds_since(t0);
            const auto t1 = std::chrono::steady_clock::now();
            retrieval::SearchOptions so;
            so.exact = a->exact;
            so.candidates = a->candidates;
            so.threads = a->threads;
            const auto matches = x.search(hist, a->top, so);
            const double search = seconds_since(t1);
            const bool two = x.two_stage(so);
            nlohmann::ordered_json list = nlohmann::ordered_json::array();
            for (const auto& mt : matches)
                list.push_back({{"name", mt.name}, {"class", mt.cls}, {"distance", mt.distance}});
            const std::size_t candidates =
                two ? std::max(a->top, a->candidates > 0 ? a->candidates : x.default_candidates(a->top))
                    : x.size();
            all.push_back({{"query", path},
                           {"method", folder},
                           {"models", x.size()},
                           {"search", two ? "two-stage" : "exhaustive"},
                           {"candidates", candidates},
                           {"matches", list},
                           {"describe_seconds", describe},
                           {"search_seconds", search}});
            if (!a->json) {
                std::cout << path << " (" << folder << ", " << x.size() << " models, "
                          << (two ? "two-stage: " + std::to_string(candidates) + " candidates"
                                  : std::string("exhaustive"))
                          << "):\n";
                int rank = 1;
                for (const auto& mt : matches) {
                    char line[400];
                    std::snprintf(line, sizeof line, "%4d  %-30s %-20s %.6f\n", rank++, mt.name.c_str(),
                                  mt.cls.c_str(), static_cast<double>(mt.distance));
                    std::cout << line;
                }
            }
        }
        if (a->json) print_json(all.size() == 1 ? all[0] : all);
    });
}

}  // namespace canonform::cli
