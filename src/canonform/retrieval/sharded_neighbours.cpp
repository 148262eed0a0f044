// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the stages of a sharded run with evaluation "neighbours" (sharded_run.h) - the index,
// each row block's nearest-neighbour lists through it, and the measures from the lists - for
// collections too large for the N x N matrix.
#include "canonform/common/parallel.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/retrieval/sharded_run.h"

#include <cstring>
#include <map>

namespace canonform::retrieval {

namespace {

/// The lists' K: the plan's (at most N - 1) or neighbours_needed().
int list_length(const ShardedPlan& plan, const std::vector<std::string>& labels) {
    const int n = static_cast<int>(labels.size());
    return plan.neighbours > 0 ? std::min(plan.neighbours, n - 1) : neighbours_needed(labels);
}

/// Rows [begin, end) of block `b` of `blocks` among n (equal blocks: every row costs one query).
std::pair<std::size_t, std::size_t> equal_rows(int b, int blocks, std::size_t n) {
    const auto B = static_cast<std::size_t>(blocks), i = static_cast<std::size_t>(b);
    return {i * n / B, (i + 1) * n / B};
}

}  // namespace

void ShardedRun::index(nlohmann::ordered_json& m) const {
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        const std::string folder = spec.folder(), dir = run_ + "/" + folder;
        const Collected c = collect(spec);
        std::vector<std::string> names, classes;
        for (std::size_t k : c.good) {
            names.push_back(experiment_.models()[k].name);
            classes.push_back(experiment_.models()[k].label);
        }
        const CollectionIndex x = index_descriptors(dir, names, classes, spec.to_string(),
                                                    plan_.experiment.simplify, plan_.experiment.threads);
        x.save(dir + "/index.cfci");
        m["outputs"].push_back(folder + "/index.cfci");
    }
}

void ShardedRun::neighbours(int block, nlohmann::ordered_json& m) const {
    for (const canonical::MethodSpec& spec : plan_.experiment.methods) {
        const std::string folder = spec.folder(), dir = run_ + "/" + folder;
        const CollectionIndex x = CollectionIndex::load(dir + "/index.cfci");
        const Collected c = collect(spec);
        if (x.size() != c.good.size())
            throw InputError("'" + dir + "/index.cfci' holds " + std::to_string(x.size()) +
                             " models, the run " + std::to_string(c.good.size()) +
                             ": the index stage is out of date (delete its marker)");
        const int k = list_length(plan_, x.classes());
        const auto rows = equal_rows(block, parts(Stage::Distances), x.size());
        const std::size_t r0 = rows.first, r1 = rows.second;
        SearchOptions o;
        o.exact = plan_.exact;
        o.threads = 1;  // one query per thread: rows in parallel
        std::string bytes((r1 - r0) * static_cast<std::size_t>(k) * 8, '\0');
        ParallelOptions par;
        par.threads = plan_.experiment.threads;
        parallel_for(
            static_cast<std::ptrdiff_t>(r1 - r0),
            [&](std::ptrdiff_t i, int) {
                const std::size_t r = r0 + static_cast<std::size_t>(i);
                SearchOptions mine = o;
                mine.self = static_cast<std::ptrdiff_t>(r);
                const auto found = x.search(x.histograms(r), static_cast<std::size_t>(k) + 1, mine);
                char* out = bytes.data() + static_cast<std::size_t>(i) * static_cast<std::size_t>(k) * 8;
                int put = 0;
                for (const auto& f : found) {
                    if (f.model == r || put == k) continue;
                    const auto model = static_cast<std::uint32_t>(f.model);
                    std::memcpy(out + 8 * put, &model, 4);
                    std::memcpy(out + 8 * put + 4, &f.distance, 4);
                    ++put;
                }
                if (put < k)
                    throw InputError("model " + x.names()[r] + ": fewer than " + std::to_string(k) +
                                     " neighbours found");
            },
            par);
        const std::string path = dir + "/stages/neighbours_" + std::to_string(block) + ".bin";
        io::make_directories(dir + "/stages");
        io::write_file_atomic(path, bytes);
        m["outputs"].push_back(folder + "/stages/neighbours_" + std::to_string(block) + ".bin");
        m["rows"][folder] = {r0, r1};
        m["neighbours"][folder] = k;
        m["search"][folder] = x.two_stage(o) ? "two-stage" : "exhaustive";
    }
}

void ShardedRun::merge_neighbours(const canonical::MethodSpec& spec, MethodOutcome& out,
                                  nlohmann::ordered_json& m) const {
    const std::string folder = spec.folder(), dir = run_ + "/" + folder;
    const Collected c = collect(spec);
    const std::size_t n = c.good.size();
    std::vector<std::string> labels;
    for (std::size_t k : c.good) labels.push_back(experiment_.models()[k].label);
    const int k = list_length(plan_, labels);
    std::vector<std::vector<std::uint32_t>> lists(n);
    std::string all;
    std::string search;
    for (int b = 0; b < parts(Stage::Distances); ++b) {
        const auto rows = equal_rows(b, parts(Stage::Distances), n);
        const std::string path = dir + "/stages/neighbours_" + std::to_string(b) + ".bin";
        const std::string bytes = io::read_file(path);
        const std::size_t expected = (rows.second - rows.first) * static_cast<std::size_t>(k) * 8;
        if (bytes.size() != expected)
            throw InputError("'" + path + "': " + std::to_string(bytes.size()) + " bytes, expected " +
                             std::to_string(expected) + " (rows " + std::to_string(rows.first) + " to " +
                             std::to_string(rows.second) + ", " + std::to_string(k) + " neighbours each)");
        for (std::size_t r = rows.first; r < rows.second; ++r)
            for (int i = 0; i < k; ++i) {
                std::uint32_t model;
                std::memcpy(
                    &model,
                    bytes.data() +
                        ((r - rows.first) * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)) * 8,
                    4);
                lists[r].push_back(model);
            }
        all += bytes;
        search = nlohmann::ordered_json::parse(io::read_file(marker(Stage::Distances, b) + ".json"))
                     .at("search")
                     .at(folder)
                     .get<std::string>();
    }
    io::write_file_atomic(dir + "/neighbours.bin", all);
    std::map<std::string, int> sizes;
    bool measurable = false;
    for (const auto& l : labels) measurable = measurable || ++sizes[l] > 2;
    nlohmann::ordered_json extra = {{"evaluation", "neighbours"}, {"neighbours", k}, {"search", search}};
    Evaluation e;
    if (measurable) {
        const NeighbourEvaluation ne = evaluate_neighbours(lists, labels, k);
        e = ne.evaluation;
        extra["dcg"] = "truncated at rank " + std::to_string(k) + ": the full DCG is at most dcg_bound above";
        extra["dcg_bound"] = {{"micro", ne.dcg_bound.dcg}, {"macro", ne.dcg_bound_macro}};
    } else {
        out.no_measures =
            "no class has more than two models among the " + std::to_string(n) +
            " meshes that succeeded: the measures need three; the neighbours are in neighbours.bin";
    }
    experiment_.finish_method(out, c.good, e, extra);
    for (const char* f :
         {"/neighbours.bin", "/models.csv", "/metrics.json", "/timings.json", "/failures.txt"})
        m["outputs"].push_back(folder + f);
}

}  // namespace canonform::retrieval
