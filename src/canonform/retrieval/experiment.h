// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: a retrieval experiment over a labelled collection - the pipeline of the paper's
// Section 6 (Tables 2-5, Figs. 10-11), as `canonform retrieve`, the benchmarks and the filters
// run it.
//
//   per mesh (in parallel, cached by file content and parameters):
//       [simplify] [noise] -> canonical form (a method of the registry) -> 66 depth views + SIFT
//   per method: codebook (trained on the method's features, or given) -> one bag-of-features
//       histogram per view -> N x N clock-matching distances -> psbTable's measures, precision-
//       recall, and pose consistency where the collection has ground-truth correspondences
//
// Everything lives in the run folder RUN: cache/ (per-mesh features and forms, codebooks),
// collection.csv, and per method METHOD/ (METHOD = MethodSpec::folder()): forms/, descriptors/, codebook.bin,
// distances.bin (+ .csv, models.csv), metrics.json (the measures only: equal for equal inputs),
// timings.json (stage seconds), pr.csv, failures.txt. A second run with the
// same inputs recomputes nothing; an added method computes only its own work.
#pragma once

#include "canonform/canonical/method_registry.h"
#include "canonform/retrieval/fused_distances.h"
#include "canonform/retrieval/retrieval_measures.h"
#include "canonform/views/view_descriptor.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace canonform::retrieval {

/// One model of a collection.
struct Model {
    std::string path;        ///< the mesh file (dataset folder + the labels file's path)
    std::string label;       ///< its class
    std::string name;        ///< file name without folder and extension (names its outputs)
    std::uint64_t hash = 0;  ///< FNV-1a of the file's bytes (the cache key's content part)
    std::string error;       ///< why the file cannot be read ("" if it can): the model is a listed failure
};

/// The collection of a labels file ("path,class" rows, paths relative to `dataset`), in order.
/// InputError naming the labels file if it cannot be read or a row is malformed, and naming the
/// models if two share a name (their outputs would overwrite each other); a mesh file that cannot
/// be read is kept with its `error` (a failure of the run, not a stop). The files are read and
/// hashed on `threads` threads (0: every core); the result does not depend on it.
std::vector<Model> read_collection(const std::string& dataset, const std::string& labels, int threads = 0);

/// What an experiment runs.
struct ExperimentOptions {
    std::string dataset;                         ///< folder the label paths are relative to
    std::string labels;                          ///< labels file ("path,class")
    std::string out;                             ///< run folder
    std::vector<canonical::MethodSpec> methods;  ///< canonical-form methods, in order (folders must differ)
    /// Fused methods (fused_distances.h), run after `methods`; a member not among `methods` is
    /// added to them.
    std::vector<FusedSpec> fused;
    int words = 1500;                          ///< codebook size (trained on each method's features)
    std::string codebook;                      ///< a given codebook instead ("" = train)
    views::CodebookOptions codebook_training;  ///< method, sample, iterations (words, seed: the fields here)
    int simplify = 0;                          ///< simplify every mesh to this many vertices first (0 = no)
    double noise = 0;                          ///< vertex noise, as a fraction of the mean edge length
    std::uint64_t seed = 0;                    ///< seeds of the noise and the codebook
    int threads = 0;                           ///< meshes in parallel (0 = every core)
    bool repair = false;                 ///< repair every mesh first (surface/mesh_repair.h; logged per mesh)
    views::ViewDescriptorOptions views;  ///< image size, pose and SIFT settings
    std::function<void(const std::string&)> log;  ///< one line per finished stage (may be empty)
    std::function<ProgressFn(const std::string& method)>
        progress;  ///< per-mesh progress of a method (may be empty)
};

/// The features of one mesh under one method.
struct MeshFeatures {
    bool ok = false;
    bool cached = false;  ///< read from the run's cache
    std::string error;    ///< why it failed (if !ok)
    std::string note;     ///< what the run should log for it (a repair, a recomputed cache entry)
    std::vector<views::SiftDescriptors> features;  ///< one matrix per view
};

/// The outcome of one method.
struct MethodOutcome {
    canonical::MethodSpec spec;
    std::string label;                 ///< a fused method's folder name ("" for a canonical-form method)
    std::vector<std::string> members;  ///< a fused method's member folders, in order (empty otherwise)
    std::string folder;                ///< RUN/METHOD
    Evaluation evaluation;
    std::string no_measures;       ///< why there are no measures ("" if there are): classes too small
    double pose_consistency = -1;  ///< -1: not measured (no correspondences, or simplified)
    int pose_consistency_pairs = 0;
    std::size_t meshes = 0, failed = 0;
    int cached = 0;  ///< meshes read from the cache
    double forms_seconds = 0, codebook_seconds = 0, distances_seconds = 0;
    /// Its name in the report: the fused method's label, else the method's folder.
    std::string name() const { return label.empty() ? spec.folder() : label; }
};

/// A retrieval run. The constructor reads and checks the collection before any work (the labels,
/// at least three models, distinct names; classes too small for the measures are logged) and
/// prepares the run folder; the stage functions can be called one by one (benchmarks, tests) or all at once
/// by run().
class Experiment {
public:
    explicit Experiment(ExperimentOptions options);
    /// The same on a collection already read (read_collection(); a sharded run reads it once).
    Experiment(ExperimentOptions options, std::vector<Model> models);

    const ExperimentOptions& options() const { return options_; }
    const std::vector<Model>& models() const { return models_; }

    /// Stage 1 for one mesh: [simplify, noise,] the canonical form (written to METHOD/forms/) and
    /// the SIFT features of its 66 views, from the cache when it has them. Never throws: a failure
    /// is returned with its reason.
    MeshFeatures mesh_features(const canonical::MethodSpec& method, std::size_t model) const;
    /// The cache entry of one mesh under one method: RUN/cache/KEY, with KEY from the file's
    /// content and the parameters; mesh_features() keeps KEY.cfvd (the features) and KEY.ply (the form).
    /// The seed is part of KEY only with noise: without it, runs that differ only in the seed (the
    /// codebook's) share the entries.
    std::string cache_entry(const canonical::MethodSpec& method, std::size_t model) const;
    /// How each method's codebook is trained (options.codebook_training with its words and seed), on
    /// the good meshes' features stacked in collection order (a sample of them: views::stacked_rows()).
    views::CodebookOptions codebook_options() const;
    /// Stage 1 for every mesh, in parallel, with progress.
    std::vector<MeshFeatures> features(const canonical::MethodSpec& method) const;
    /// Stage 2: the given codebook, or one trained on the features of the meshes `good` (cached).
    views::Codebook codebook(const canonical::MethodSpec& method, const std::vector<MeshFeatures>& features,
                             const std::vector<std::size_t>& good) const;
    /// The last stage of a method from its distances D between the meshes `good` (in order):
    /// writes distances.bin (+ .csv), models.csv, metrics.json, timings.json (out's seconds, plus
    /// this stage's), pr.csv; fills out.evaluation / no_measures and the pose consistency. `out`
    /// carries spec, folder, meshes, failed and the seconds of the earlier stages.
    void finish_method(MethodOutcome& out, const std::vector<std::size_t>& good,
                       const Eigen::MatrixXf& D) const;
    /// The same from measures computed without the matrix (each model's nearest neighbours,
    /// retrieval_measures.h): no distances.bin or pr.csv; `extra` is added to metrics.json.
    void finish_method(MethodOutcome& out, const std::vector<std::size_t>& good, const Evaluation& evaluation,
                       const nlohmann::ordered_json& extra) const;
    /// Every stage of one method; writes its folder.
    MethodOutcome run_method(const canonical::MethodSpec& method) const;
    /// A fused method from its members' distance matrices (RUN/MEMBER/distances.bin, written by
    /// run_method()) over the models every member has; writes its folder like run_method().
    MethodOutcome run_fused(const FusedSpec& fused) const;
    /// Every method, in order, then every fused method.
    std::vector<MethodOutcome> run() const;

private:
    /// models.csv, pose consistency, metrics.json (with `extra`), timings.json of a method.
    void finish_measures(MethodOutcome& out, const std::vector<std::size_t>& good,
                         const nlohmann::ordered_json& extra) const;
    ExperimentOptions options_;
    std::vector<Model> models_;
    /// Each model's conformal factor, kept between the run's Euclidean methods (with two or more
    /// of them) while the kept ones fit in 256 MB: computed once per mesh, the same forms.
    struct ConformalFactors;
    std::shared_ptr<ConformalFactors> conformal_factors_;
};

/// RUN/report.md of a run: the collection, one table row per method, the summary (summary_markdown),
/// then `pictures` (markdown lines: the precision-recall plot, the grid) and the notes on the measures.
std::string report_markdown(const ExperimentOptions& options, std::size_t meshes,
                            const std::vector<MethodOutcome>& outcomes, const std::string& pictures);

/// What a user acts on after a run of several methods (markdown, "" for fewer than two measured
/// methods): the best method per measure (NN, 1-Tier, 2-Tier, E-measure, DCG; ties named
/// together, compared at the three decimals the table shows), and for every fused method whose
/// members were run, the measures on which it does not beat its best member, with both figures
/// (or that it beats every member on all five).
std::string summary_markdown(const std::vector<MethodOutcome>& outcomes);

/// Pose consistency of a method's forms (FOLDER/forms/NAME.ply) against ground-truth
/// correspondences (DATASET/corres/NAME.vts, line k = the 1-based vertex at template point k):
/// over same-class pairs, the RMS distance between corresponding vertices after the best rigid
/// motion or mirror image (MDS fixes a form only up to one), relative to the RMS radius of the
/// second; the mean over pairs, or -1 if no pair has correspondences. Forms are read and pairs
/// aligned on `threads` threads (0: every core); the result does not depend on them.
double pose_consistency(const std::vector<Model>& models, const std::vector<std::size_t>& good,
                        const std::string& dataset, const std::string& forms_dir, int* pairs,
                        int threads = 0);

}  // namespace canonform::retrieval
