// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: a retrieval run (experiment.h) split into stages that run apart - on several
// machines sharing the run folder, e.g. as the job arrays of a Slurm cluster (`canonform slurm`).
//
//   init                 the plan (RUN/sharded.json) and the collection read once (RUN/models.json)
//   features  shard I/N  per mesh of shard I: [simplify, noise,] canonical form, 66 views, SIFT
//   codebook             trained as Experiment::codebook() does (a seeded sample, views/codebook.h)
//   histograms shard I/N one bag-of-features histogram per view, per mesh of shard I
//   index                (evaluation "neighbours" only) each method's collection index with its
//                        first pass (collection_index.h), METHOD/index.cfci
//   distances block B/NB rows of the upper triangle of the N x N clock-matching matrix, the row
//                        blocks balanced by pair count (views::distance_rows()); with evaluation
//                        "neighbours", instead each row's K nearest other models through the index
//                        (equal row blocks; METHOD/stages/neighbours_B.bin)
//   merge                the matrix, measures, pose consistency, report (Experiment::finish_method());
//                        with "neighbours", the measures from the lists (retrieval_measures.h:
//                        NN, tiers and E-measure exactly the matrix's, DCG truncated at K) and
//                        METHOD/neighbours.bin instead of the matrix
//
// Every stage runs every method of the plan. All state lives in the run folder: a finished stage
// writes its marker RUN/stages/STAGE_I.json last (atomically, like every output: temporary file +
// rename), listing its outputs; a stage is done when its marker exists and every output it lists
// does, so a stage killed mid-way or an output deleted later is redone, and only that stage: a
// second call of a done stage does nothing. A stage that fails leaves RUN/stages/STAGE_I.failed
// (the message) until it succeeds. The stages compute what `canonform retrieve` computes, in the
// same order, so a sharded run gives the same bytes of distances.bin and metrics.json as
// `retrieve` with the same options (timings are apart, in timings.json).
#pragma once

#include "canonform/retrieval/experiment.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace canonform::retrieval {

/// What a sharded run computes: the experiment's options and how it is split.
struct ShardedPlan {
    ExperimentOptions experiment;  ///< dataset, labels, out (the run folder), methods, words, ...
    int shards = 1;                ///< mesh shards (features, histograms)
    int blocks = 0;                ///< row blocks of the distance matrix (0 = as many as shards)
    /// "matrix" (the N x N matrix) or "neighbours" (each model's K nearest through the index,
    /// for collections too large for the matrix).
    std::string evaluation = "matrix";
    int neighbours = 0;  ///< K of "neighbours" (0 = max(2 x largest class, 32), at most N - 1)
    bool exact = false;  ///< "neighbours" by exhaustive clock matching even above the two-stage size
};

/// neighbours.bin of a "neighbours" run: per model (models.csv order) K x (u32 model, f32 distance),
/// little endian, nearest first, the model itself left out.

/// The stages, in order.
enum class Stage { Features, Codebook, Histograms, Index, Distances, Merge };
/// "features", "codebook", "histograms", "index", "distances", "merge".
const char* stage_name(Stage s);
/// The stage named `name` (InputError listing the names if none).
Stage parse_stage(const std::string& name);

/// Where one stage of a run stands.
struct StageStatus {
    Stage stage = Stage::Features;
    int parts = 1;  ///< shards, blocks, or 1
    std::vector<int> done, failed, pending;
    std::vector<std::string> errors;  ///< the message of each failed part
    double seconds = 0;               ///< summed over the done parts
};

/// Writes the plan of a new run (RUN/sharded.json) and reads the collection once (RUN/models.json,
/// RUN/collection.csv). Idempotent: the same plan again does nothing; a different plan in the same
/// folder is an InputError (start another folder). InputError for bad input, as Experiment.
void init_sharded_run(const ShardedPlan& plan);

/// A run folder made by init_sharded_run(), and its stages.
class ShardedRun {
public:
    /// Reads RUN/sharded.json and RUN/models.json (InputError if the folder is not a sharded run).
    /// `threads`: meshes or rows in parallel within a stage (0 = every core); `log` as the experiment's.
    explicit ShardedRun(const std::string& run, int threads = 0,
                        std::function<void(const std::string&)> log = {});

    const ShardedPlan& plan() const { return plan_; }
    const Experiment& experiment() const { return experiment_; }
    /// Parts of a stage: shards, blocks or 1 (0: the index stage of a "matrix" run, which it skips).
    int parts(Stage s) const;

    /// Runs part `index` of stage `s` unless it is done; returns false if it was. InputError if an
    /// earlier stage it needs is not done (naming the parts) or `index` is out of range; any
    /// failure leaves RUN/stages/STAGE_I.failed with the message and is rethrown.
    bool run(Stage s, int index = 0) const;
    /// Every part of every stage in order, here (a one-machine run of the stages).
    void run_all() const;
    /// True if part `index` of `s` is done (marker present and every output it lists present).
    bool done(Stage s, int index = 0) const;
    /// Every stage's parts: done, failed, pending (stages of no parts left out).
    std::vector<StageStatus> status() const;

    /// The meshes [begin, end) of shard `shard` (contiguous, sizes differing by at most one).
    std::pair<std::size_t, std::size_t> shard_models(int shard) const;
    /// The rows [begin, end) of block `block` among `n` good meshes, balanced by pair count.
    std::pair<std::size_t, std::size_t> block_rows(int block, std::size_t n) const;

private:
    std::string marker(Stage s, int index) const;
    void features(int shard, nlohmann::ordered_json& m) const;
    void codebook(nlohmann::ordered_json& m) const;
    void histograms(int shard, nlohmann::ordered_json& m) const;
    void index(nlohmann::ordered_json& m) const;
    void distances(int block, nlohmann::ordered_json& m) const;
    void neighbours(int block, nlohmann::ordered_json& m) const;
    void merge(nlohmann::ordered_json& m) const;
    void merge_neighbours(const canonical::MethodSpec& spec, MethodOutcome& out,
                          nlohmann::ordered_json& m) const;
    bool by_neighbours() const { return plan_.evaluation == "neighbours"; }
    /// Per method folder, the meshes that succeeded (in collection order) and the failures, from
    /// the features markers.
    struct Collected {
        std::vector<std::size_t> good;
        std::string failures;  ///< "name: error" lines
        std::vector<std::string> notes;
        std::vector<std::size_t> rows;  ///< descriptors per good mesh
        int cached = 0;
        double seconds = 0;
    };
    Collected collect(const canonical::MethodSpec& method) const;

    std::string run_;
    ShardedPlan plan_;
    Experiment experiment_;
    std::function<void(const std::string&)> log_;
};

}  // namespace canonform::retrieval
