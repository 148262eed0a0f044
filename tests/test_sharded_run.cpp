// SPDX-License-Identifier: GPL-3.0-or-later
// The sharded retrieval run: the same bytes as the one-machine Experiment, resumable stages that
// redo only what is missing, the order of stages, and the codebook's training sample.
#include "canonform/common/errors.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/retrieval/sharded_run.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <set>

using namespace canonform;
using namespace canonform::retrieval;
using namespace canonform::canonical;
using namespace canonform::procedural;
namespace fs = std::filesystem;

namespace {

/// A folder in the temporary directory, of this process (ctest runs tests in parallel processes,
/// and other checkouts' tests may run on the same machine).
std::string temp(const std::string& name) {
    return canonform::test::process_temp_path(name);
}

/// Seven figures (two body types, 600 vertices) in a folder of their own per `tag`.
std::string make_collection(const std::string& tag) {
    const std::string d = temp("canonform_test_sharded_" + tag);
    fs::remove_all(d);
    io::make_directories(d + "/meshes");
    std::string labels = "path,class\n";
    int i = 0;
    for (const std::string cls : {"standard", "long-arms"})
        for (int pose = 0; pose < (cls == "standard" ? 4 : 3); ++pose, ++i) {
            const Figure f = make_figure(600, figure_pose(pose), figure_class(cls));
            const std::string name = cls + "_" + std::to_string(pose) + ".ply";
            io::write_ply(d + "/meshes/" + name, f.mesh.V, f.mesh.F);
            labels += "meshes/" + name + "," + cls + "\n";
        }
    io::write_file_atomic(d + "/labels.csv", labels);
    return d;
}

ExperimentOptions options(const std::string& dataset, const std::string& out, std::size_t sample) {
    ExperimentOptions o;
    o.dataset = dataset;
    o.labels = dataset + "/labels.csv";
    o.out = out;
    o.methods = {parse_method_spec("none")};
    o.words = 24;
    o.seed = 7;
    o.codebook_training.sample = static_cast<std::int64_t>(sample);
    o.threads = 2;
    return o;
}

const char* const kCompared[] = {"/none/distances.bin", "/none/metrics.json", "/none/models.csv",
                                 "/none/pr.csv", "/none/failures.txt"};

fs::file_time_type mtime(const std::string& p) {
    return fs::last_write_time(p);
}

}  // namespace

TEST(ShardedRun, BlocksAreBalancedAndCoverEveryRow) {
    const std::string data = make_collection("blocks");
    const std::string run = temp("canonform_test_sharded_blocks_run");
    fs::remove_all(run);
    ShardedPlan p;
    p.experiment = options(data, run, 0);
    p.shards = 3;
    p.blocks = 4;
    init_sharded_run(p);
    const ShardedRun r(run);
    EXPECT_EQ(r.parts(Stage::Features), 3);
    EXPECT_EQ(r.parts(Stage::Distances), 4);
    EXPECT_EQ(r.parts(Stage::Merge), 1);
    std::size_t next = 0;
    for (int s = 0; s < 3; ++s) {
        const auto [b, e] = r.shard_models(s);
        EXPECT_EQ(b, next);
        EXPECT_GE(e - b, 2u);
        next = e;
    }
    EXPECT_EQ(next, 7u);
    // 1000 rows: each block holds about a quarter of the 499500 pairs.
    next = 0;
    for (int b = 0; b < 4; ++b) {
        const auto [r0, r1] = r.block_rows(b, 1000);
        EXPECT_EQ(r0, next);
        double pairs = 0;
        for (std::size_t i = r0; i < r1; ++i) pairs += static_cast<double>(1000 - 1 - i);
        EXPECT_NEAR(pairs / 499500.0, 0.25, 0.01) << b;
        next = r1;
    }
    EXPECT_EQ(next, 1000u);
    // The same plan again is a no-op; another plan in the same folder is refused.
    EXPECT_NO_THROW(init_sharded_run(p));
    p.shards = 2;
    EXPECT_THROW(init_sharded_run(p), InputError);
    // Stages in order: the codebook needs every features shard.
    EXPECT_THROW(r.run(Stage::Codebook), InputError);
    EXPECT_THROW(r.run(Stage::Features, 3), InputError);
    EXPECT_THROW(ShardedRun(run + "_none"), InputError);
}

TEST(ShardedRun, SameBytesAsTheOneMachineRunAndRedoesOnlyWhatIsMissing) {
    const std::string data = make_collection("same");
    for (const std::size_t sample : {std::size_t{0}, std::size_t{400}}) {
        SCOPED_TRACE("codebook sample " + std::to_string(sample));
        const std::string tag = std::to_string(sample);
        const std::string one = temp("canonform_test_sharded_one_" + tag);
        const std::string run = temp("canonform_test_sharded_run_" + tag);
        fs::remove_all(one);
        fs::remove_all(run);
        Experiment(options(data, one, sample)).run();

        ShardedPlan p;
        p.experiment = options(data, run, sample);
        p.shards = 3;
        p.blocks = 2;
        init_sharded_run(p);
        std::vector<std::string> log;
        const ShardedRun r(run, 2, [&](const std::string& l) {
            if (l.find("] done in") != std::string::npos) log.push_back(l);
        });
        r.run_all();
        for (const char* f : kCompared) EXPECT_EQ(io::read_file(run + f), io::read_file(one + f)) << f;
        EXPECT_TRUE(io::is_file(run + "/none/timings.json"));
        EXPECT_TRUE(io::is_file(run + "/report.md"));
        EXPECT_EQ(log.size(), 3u + 1 + 3 + 2 + 1);
        for (const auto& s : r.status()) {
            EXPECT_EQ(s.done.size(), static_cast<std::size_t>(s.parts)) << stage_name(s.stage);
            EXPECT_TRUE(s.pending.empty() && s.failed.empty());
        }

        // Everything done: a second pass does nothing.
        log.clear();
        r.run_all();
        EXPECT_TRUE(log.empty());

        // A deleted output of features shard 1 (a cached descriptor) and a partial marker of
        // histograms shard 2: those two parts are pending, and only they are redone.
        const std::string m0 = run + "/stages/features_0.json", m2 = run + "/stages/features_2.json";
        const auto t0 = mtime(m0), t2 = mtime(m2);
        const auto [b1, e1] = r.shard_models(1);
        fs::remove(r.experiment().cache_entry(p.experiment.methods[0], b1) + ".cfvd");
        const std::string h2 = run + "/stages/histograms_2.json";
        const std::string partial = io::read_file(h2);
        io::write_file_atomic(h2, partial.substr(0, partial.size() / 2));
        EXPECT_FALSE(r.done(Stage::Features, 1));
        EXPECT_FALSE(r.done(Stage::Histograms, 2));
        EXPECT_TRUE(r.done(Stage::Features, 0));
        const auto st = r.status();
        EXPECT_EQ(st[0].pending, std::vector<int>{1});
        EXPECT_EQ(st[2].pending, std::vector<int>{2});
        log.clear();
        r.run_all();
        ASSERT_EQ(log.size(), 2u);
        EXPECT_NE(log[0].find("[features 1/3]"), std::string::npos) << log[0];
        EXPECT_NE(log[1].find("[histograms 2/3]"), std::string::npos) << log[1];
        EXPECT_EQ(mtime(m0), t0);
        EXPECT_EQ(mtime(m2), t2);
        EXPECT_TRUE(io::is_file(r.experiment().cache_entry(p.experiment.methods[0], b1) + ".cfvd"));

        // Redoing the later stages gives the same bytes.
        for (int b = 0; b < 2; ++b) fs::remove(run + "/stages/distances_" + std::to_string(b) + ".json");
        fs::remove(run + "/none/distances.bin");
        r.run_all();
        for (const char* f : kCompared) EXPECT_EQ(io::read_file(run + f), io::read_file(one + f)) << f;
    }
}

TEST(ShardedRun, AFailedStageLeavesItsMessageUntilItSucceeds) {
    const std::string data = make_collection("failed");
    const std::string run = temp("canonform_test_sharded_failed_run");
    fs::remove_all(run);
    ShardedPlan p;
    p.experiment = options(data, run, 0);
    p.experiment.codebook = run + "_missing_codebook.bin";
    fs::remove(p.experiment.codebook);
    p.shards = 1;
    init_sharded_run(p);
    const ShardedRun r(run, 2);
    EXPECT_TRUE(r.run(Stage::Features, 0));
    EXPECT_THROW(r.run(Stage::Codebook), InputError);
    const auto st = r.status();
    EXPECT_EQ(st[1].failed, std::vector<int>{0});
    ASSERT_EQ(st[1].errors.size(), 1u);
    EXPECT_NE(st[1].errors[0].find("missing_codebook"), std::string::npos) << st[1].errors[0];
    // The given codebook appears: the stage succeeds and its failure is gone.
    views::CodebookOptions co;
    co.words = 4;
    views::Codebook::train(views::DescriptorMatrix::Random(50, 128).cwiseAbs(), co)
        .save(p.experiment.codebook);
    EXPECT_TRUE(r.run(Stage::Codebook));
    EXPECT_TRUE(r.status()[1].failed.empty());
    EXPECT_FALSE(io::is_file(run + "/stages/codebook_0.failed"));
}

TEST(ShardedRun, NeighbourEvaluationGivesTheMatrixMeasuresWithoutTheMatrix) {
    const std::string data = make_collection("neighbours");
    const std::string one = temp("canonform_test_sharded_nb_one"),
                      run = temp("canonform_test_sharded_nb_run");
    fs::remove_all(one);
    fs::remove_all(run);
    Experiment(options(data, one, 0)).run();
    ShardedPlan p;
    p.experiment = options(data, run, 0);
    p.shards = 2;
    p.blocks = 3;
    p.evaluation = "neighbours";
    init_sharded_run(p);
    // the features, computed once, entry by entry into the cache folder the run made (MinGW's
    // std::filesystem::copy refuses a folder onto an existing one: "File exists")
    fs::create_directories(run + "/cache");
    for (const auto& e : fs::directory_iterator(one + "/cache"))
        fs::copy(e.path(), fs::path(run + "/cache") / e.path().filename(), fs::copy_options::recursive);
    const ShardedRun r(run, 2);
    EXPECT_EQ(r.parts(Stage::Index), 1);
    EXPECT_THROW(r.run(Stage::Index), InputError);  // needs the histograms first
    r.run_all();
    EXPECT_FALSE(io::is_file(run + "/none/distances.bin"));
    EXPECT_FALSE(io::is_file(run + "/none/pr.csv"));
    EXPECT_TRUE(io::is_file(run + "/none/index.cfci"));
    EXPECT_EQ(io::read_file(run + "/none/models.csv"), io::read_file(one + "/none/models.csv"));
    const auto got = nlohmann::json::parse(io::read_file(run + "/none/metrics.json"));
    const auto want = nlohmann::json::parse(io::read_file(one + "/none/metrics.json"));
    EXPECT_EQ(got["evaluation"], "neighbours");
    EXPECT_EQ(got["neighbours"], 6);  // max(2 x 4, 32) models, at most the 6 others
    EXPECT_EQ(got["search"], "exhaustive");
    for (const char* avg : {"micro", "macro"})
        for (const char* key : {"nn", "first_tier", "second_tier", "e_measure", "dcg", "queries"})
            EXPECT_EQ(got[avg][key], want[avg][key])
                << avg << " " << key;  // every other model listed: DCG too
    // neighbours.bin: each model's row of the matrix in ranking order, itself left out.
    const Eigen::MatrixXd D = io::read_distance_matrix(one + "/none/distances.bin");
    const std::string nb = io::read_file(run + "/none/neighbours.bin");
    ASSERT_EQ(nb.size(), 7u * 6 * 8);
    for (int q = 0; q < 7; ++q) {
        std::vector<int> order;
        for (int j = 0; j < 7; ++j)
            if (j != q) order.push_back(j);
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return D(q, a) < D(q, b); });
        for (int i = 0; i < 6; ++i) {
            std::uint32_t m;
            float d;
            std::memcpy(&m, nb.data() + (q * 6 + i) * 8, 4);
            std::memcpy(&d, nb.data() + (q * 6 + i) * 8 + 4, 4);
            EXPECT_EQ(m, static_cast<std::uint32_t>(order[static_cast<std::size_t>(i)])) << q << " " << i;
            EXPECT_EQ(d, static_cast<float>(D(q, order[static_cast<std::size_t>(i)]))) << q << " " << i;
        }
    }
    // A matrix run has no index stage.
    ShardedPlan q = p;
    q.evaluation = "matrix";
    q.experiment.out = run + "_matrix";
    fs::remove_all(q.experiment.out);
    init_sharded_run(q);
    const ShardedRun m(q.experiment.out);
    EXPECT_EQ(m.parts(Stage::Index), 0);
    EXPECT_THROW(m.run(Stage::Index), InputError);
    for (const auto& s : m.status()) EXPECT_NE(s.stage, Stage::Index);
    q.evaluation = "other";
    q.experiment.out = run + "_other";
    EXPECT_THROW(init_sharded_run(q), InputError);
}
