// canonform tool: a retrieval run beyond one machine - stage (one stage, one shard) and status.
#include "cli.h"

#include "canonform/io/files.h"
#include "canonform/retrieval/sharded_run.h"

#include <cstdio>
#include <iostream>
#include <memory>

namespace canonform::cli {

namespace {

std::string join(const std::vector<int>& v) {
    std::string s;
    for (int i : v) s += (s.empty() ? "" : ",") + std::to_string(i);
    return s.empty() ? "-" : s;
}

}  // namespace

void add_stage(CLI::App& app) {
    struct Args {
        retrieval::ShardedPlan plan;
        std::string methods = "none,euclidean-N";
        std::string run, stage;
        int shard = -1, threads = 0;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand(
        "stage", "one stage of a sharded retrieval run (state in the run folder, every stage resumable): init, "
                 "features, codebook, histograms, distances, merge, or all");
    c->require_subcommand(1);

    auto* init = c->add_subcommand("init", "start a sharded run: the plan and the collection, read once");
    auto& o = a->plan.experiment;
    init->add_option("--dataset", o.dataset, "collection folder (label paths are relative to it)")->required();
    init->add_option("--labels", o.labels, "labels file, rows path,class (default: DATASET/labels.csv)");
    init->add_option("--out", o.out, "run folder (on a filesystem every machine shares)")->required();
    init->add_option("--shards", a->plan.shards, "mesh shards")->check(CLI::Range(1, 1000000));
    init->add_option("--blocks", a->plan.blocks, "row blocks of the distance matrix (0: as many as shards)")
        ->check(CLI::Range(0, 1000000));
    init->add_option("--method", a->methods, "comma-separated methods, each NAME[:KEY=VALUE...]");
    init->add_option("--words", o.words, "codebook size")->check(CLI::Range(1, 1000000));
    init->add_option("--codebook", o.codebook, "a given codebook instead of one trained per method");
    init->add_option("--codebook-sample", o.codebook_sample,
                     "train the codebook on a seeded sample of this many descriptors (0: all)");
    init->add_option("--simplify", o.simplify, "simplify every mesh to this many vertices first (0: no)")
        ->check(CLI::Range(0, 100000000));
    init->add_option("--noise", o.noise, "vertex noise, as a fraction of the mean edge length")->check(finite_range(0, 10));
    init->add_option("--seed", o.seed, "seed of the noise and the codebook")->check(finite_range(0, 4294967295.0));
    add_repair_flag(init, o.repair);
    init->callback([a] {
        retrieval::ShardedPlan p = a->plan;
        if (p.experiment.labels.empty()) p.experiment.labels = p.experiment.dataset + "/labels.csv";
        for (const std::string& m : split_list(a->methods)) p.experiment.methods.push_back(parse_method_spec(m));
        p.experiment.log = [](const std::string& line) { std::cerr << line << "\n"; };
        retrieval::init_sharded_run(p);
        std::cerr << "stage init: " << p.experiment.out << " (" << p.shards << " shards)\n";
    });

    for (const char* name : {"features", "codebook", "histograms", "distances", "merge", "all"}) {
        const std::string n = name;
        const bool sharded = n == "features" || n == "histograms" || n == "distances";
        auto* s = c->add_subcommand(n, n == "all" ? "every stage of the run, here, skipping what is done"
                                                  : "the " + n + " stage" + (sharded ? " of one part" : ""));
        s->add_option("RUN", a->run, "the run folder (`canonform stage init`)")->required();
        if (sharded)
            s->add_option("--shard", a->shard, n == "distances" ? "the row block (0-based)" : "the shard (0-based)")
                ->required()
                ->check(CLI::Range(0, 1000000));
        s->add_option("--threads", a->threads, "meshes or rows in parallel (0: every core)")->check(CLI::Range(0, 1024));
        s->callback([a, n] {
            const retrieval::ShardedRun r(a->run, a->threads, [](const std::string& line) { std::cerr << line << "\n"; });
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
    auto* c = app.add_subcommand("status", "where a sharded run stands: per stage the parts done, failed and "
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
            if (todo && !s.done.empty()) est = s.seconds / static_cast<double>(s.done.size()) * static_cast<double>(todo);
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
            std::cout << "| " << retrieval::stage_name(s.stage) << " | " << s.parts << " | " << s.done.size() << " | "
                      << join(s.failed) << " | " << join(s.pending) << " | " << sec << " |\n";
        }
        for (const auto& s : st)
            for (std::size_t k = 0; k < s.failed.size(); ++k)
                std::cout << "failed: " << retrieval::stage_name(s.stage) << " " << s.failed[k] << ": " << s.errors[k] << "\n";
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

}  // namespace canonform::cli
