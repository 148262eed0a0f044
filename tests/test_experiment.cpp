// SPDX-License-Identifier: GPL-3.0-or-later
// The retrieval Experiment on a small generated collection: outputs, cache, measures, and a
// method added to the registry at run time.
#include "canonform/common/errors.h"
#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/numerics/rigid_alignment.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/retrieval/experiment.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include <unistd.h>

using namespace canonform;
using namespace canonform::canonical;
using namespace canonform::procedural;
namespace fs = std::filesystem;

namespace {

/// Six figures (two body types x three poses, 700 vertices) and their labels, in a folder of
/// their own per `tag` and process (ctest runs the tests of this file in parallel processes, and
/// each process writes the folders it uses afresh: a shared folder was removed under another test).
std::string make_collection(const std::string& tag = "data") {
    static std::map<std::string, std::string> made;
    if (made.count(tag)) return made[tag];
    const std::string dir = [&] {
        const std::string d = canonform::test::process_temp_path("canonform_test_experiment_" + tag);
        fs::remove_all(d);
        io::make_directories(d + "/meshes");
        std::string labels = "path,class\n";
        for (const std::string cls : {"standard", "long-arms"})
            for (int pose = 0; pose < 3; ++pose) {
                const Figure f = make_figure(700, figure_pose(pose), figure_class(cls));
                const std::string name = cls + "_" + std::to_string(pose) + ".ply";
                io::write_ply(d + "/meshes/" + name, f.mesh.V, f.mesh.F);
                labels += "meshes/" + name + "," + cls + "\n";
            }
        io::write_file_atomic(d + "/labels.csv", labels);
        return d;
    }();
    return made[tag] = dir;
}

retrieval::ExperimentOptions options(const std::string& run, const std::vector<std::string>& methods) {
    retrieval::ExperimentOptions o;
    o.dataset = make_collection();
    o.labels = o.dataset + "/labels.csv";
    // Per process: other checkouts' tests (and the sanitizer build's) run on the same machine.
    o.out = canonform::test::process_temp_path(run);
    for (const auto& m : methods) o.methods.push_back(parse_method_spec(m));
    o.words = 20;
    o.threads = 2;
    return o;
}

}  // namespace

TEST(Experiment, WritesEveryOutputAndReusesItsCache) {
    auto o = options("canonform_test_experiment_run", {"none", "euclidean-N:beta=65"});
    fs::remove_all(o.out);
    std::vector<std::string> log;
    o.log = [&](const std::string& line) { log.push_back(line); };
    const retrieval::Experiment e(o);
    ASSERT_EQ(e.models().size(), 6u);
    const auto first = e.run();
    ASSERT_EQ(first.size(), 2u);
    const std::string dir = o.out + "/euclidean-N_beta65";
    EXPECT_EQ(first[1].folder, dir);
    EXPECT_EQ(first[1].meshes, 6u);
    EXPECT_EQ(first[1].cached, 0);
    for (const char* f : {"/distances.bin", "/distances.csv", "/models.csv", "/metrics.json", "/pr.csv",
                          "/failures.txt", "/forms/standard_0.ply", "/descriptors/long-arms_2.cfvd"})
        EXPECT_TRUE(io::is_file(dir + f)) << f;
    const Eigen::MatrixXd D = io::read_distance_matrix(dir + "/distances.bin");
    ASSERT_EQ(D.rows(), 6);
    EXPECT_EQ(D.diagonal().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_LT((D - D.transpose()).cwiseAbs().maxCoeff(), 1e-6);
    const auto metrics = nlohmann::json::parse(io::read_file(dir + "/metrics.json"));
    EXPECT_EQ(metrics["beta"], 65.0);
    EXPECT_EQ(metrics["base"], "euclidean-N");
    EXPECT_EQ(metrics["micro"]["queries"], 6);
    EXPECT_NEAR(metrics["micro"]["nn"].get<double>(), first[1].evaluation.micro.nn, 1e-12);
    EXPECT_EQ(io::read_csv(dir + "/pr.csv").size(), 21u);
    // A second run reads every mesh from the cache and gives the same distances.
    const std::string bytes = io::read_file(dir + "/distances.bin");
    const auto second = retrieval::Experiment(o).run();
    EXPECT_EQ(second[1].cached, 6);
    EXPECT_EQ(io::read_file(dir + "/distances.bin"), bytes);
    EXPECT_NE(std::find_if(log.begin(), log.end(),
                           [](const std::string& l) {
                               return l.find("(6 from the cache, 0 failed)") != std::string::npos;
                           }),
              log.end());
    const std::string report = retrieval::report_markdown(o, 6, second, "");
    EXPECT_NE(report.find("| euclidean-N_beta65 |"), std::string::npos);
}

TEST(Experiment, ASeedSharesTheViewsAndNoiseDoesNot) {
    // The seed seeds the codebook (and the noise): without noise, a run with another seed takes
    // every form and view from the cache and trains its own codebook; with noise it recomputes.
    auto o = options("canonform_test_experiment_seed", {"none"});
    fs::remove_all(o.out);
    const retrieval::Experiment e0(o);
    ASSERT_EQ(e0.run()[0].cached, 0);
    auto o1 = o;
    o1.seed = 1;
    const retrieval::Experiment e1(o1);
    EXPECT_EQ(e1.cache_entry(o.methods[0], 0), e0.cache_entry(o.methods[0], 0));
    EXPECT_EQ(e1.run()[0].cached, 6);
    const auto codebooks = [&] {
        std::size_t n = 0;
        for (const auto& f : fs::directory_iterator(o.out + "/cache"))
            n += f.path().filename().string().rfind("codebook_", 0) == 0;
        return n;
    };
    EXPECT_EQ(codebooks(), 2u);
    // Noise (and simplification) change the features, so the codebook too: a noisy run in the
    // same folder trains its own instead of taking the plain run's.
    auto noisy = o;
    noisy.noise = 0.1;
    EXPECT_EQ(retrieval::Experiment(noisy).run()[0].cached, 0);
    auto simplified = o;
    simplified.simplify = 300;
    EXPECT_EQ(retrieval::Experiment(simplified).run()[0].cached, 0);
    EXPECT_EQ(codebooks(), 4u);
    auto n0 = o, n1 = o1;
    n0.noise = n1.noise = 0.1;
    EXPECT_NE(retrieval::Experiment(n0).cache_entry(o.methods[0], 0),
              retrieval::Experiment(n1).cache_entry(o.methods[0], 0));
    EXPECT_NE(retrieval::Experiment(n0).cache_entry(o.methods[0], 0), e0.cache_entry(o.methods[0], 0));
}

TEST(Experiment, FailuresAreListedAndBadCollectionsRefused) {
    auto o = options("canonform_test_experiment_bad", {"none"});
    o.labels = o.out + "_labels.csv";
    io::write_file_atomic(o.labels, "meshes/standard_0.ply,a\nmeshes/nothere.ply,a\n");
    EXPECT_THROW(retrieval::Experiment{o}, InputError);  // a missing mesh
    io::write_file_atomic(o.labels, "meshes/standard_0.ply,a\nmeshes/standard_1.ply,a\n");
    EXPECT_THROW(retrieval::Experiment{o}, InputError);  // fewer than three meshes
    o.methods.push_back(parse_method_spec("none"));
    io::write_file_atomic(o.labels,
                          "meshes/standard_0.ply,a\nmeshes/standard_1.ply,a\nmeshes/standard_2.ply,b\n");
    EXPECT_THROW(retrieval::Experiment{o}, InputError);  // a method named twice
}

TEST(Experiment, AMethodAddedToTheRegistryRunsLikeTheOthers) {
    // The mesh scaled about its centroid: the view descriptor normalises scale, so its distances
    // equal those of `none`.
    CanonicalMethod toy;
    toy.name = "toy-scaled";
    toy.label = "toy";
    toy.parameters = {Parameter::number("scale", 0.1, 10).default_value("2").help("scale factor")};
    toy.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi&, const MethodSettings& s,
                 const MethodContext&) {
        CanonicalForm r;
        r.V = V * s.number("scale");
        return r;
    };
    register_canonical_method(toy);
    auto o = options("canonform_test_experiment_toy", {"none", "toy-scaled:scale=3"});
    fs::remove_all(o.out);
    const auto out = retrieval::Experiment(o).run();
    unregister_canonical_method("toy-scaled");
    const Eigen::MatrixXd a = io::read_distance_matrix(o.out + "/none/distances.bin");
    const Eigen::MatrixXd b = io::read_distance_matrix(o.out + "/toy-scaled_scale3/distances.bin");
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 0.05);
    EXPECT_EQ(out[1].spec.to_string(), "toy-scaled:scale=3");
}

TEST(Experiment, EachMeshsConformalFactorIsComputedOnceForBothVariants) {
    // Two Euclidean methods in one run share each mesh's conformal factor: counted through two
    // methods of that family that ask the run for it, ...
    std::atomic<int> computed{0};
    const auto toy_method = [&](const std::string& name) {
        CanonicalMethod m;
        m.name = name;
        m.label = name;
        m.family = MethodFamily::Euclidean;
        m.run = [&computed](const Eigen::MatrixXd& V, const Eigen::MatrixXi&, const MethodSettings&,
                            const MethodContext& c) {
            const auto compute = [&] {
                ++computed;
                surface::ConformalFactorResult r;
                r.normalized = V.col(0);
                return r;
            };
            const surface::ConformalFactorResult cf =
                c.conformal_factors ? c.conformal_factors("toy", compute) : compute();
            CanonicalForm r;
            r.V = V;
            r.V.col(0) += cf.normalized;
            return r;
        };
        return m;
    };
    register_canonical_method(toy_method("toy-cf-one"));
    register_canonical_method(toy_method("toy-cf-two"));
    auto o = options("canonform_test_experiment_shared_cf", {"toy-cf-one", "toy-cf-two"});
    fs::remove_all(o.out);
    retrieval::Experiment(o).run();
    EXPECT_EQ(computed.load(), 6);  // six meshes, not twelve
    unregister_canonical_method("toy-cf-one");
    unregister_canonical_method("toy-cf-two");
    // ... and the forms of euclidean-N and euclidean-A run together are the bytes of each form
    // computed on its own.
    o = options("canonform_test_experiment_shared_cf_both", {"euclidean-N", "euclidean-A"});
    fs::remove_all(o.out);
    retrieval::Experiment(o).run();
    for (const std::string variant : {"euclidean-N", "euclidean-A"})
        for (const std::string model : {"standard_0", "long-arms_2"}) {
            const Mesh m = io::read_mesh(o.dataset + "/meshes/" + model + ".ply");
            MethodContext context;
            context.threads = 1;
            const CanonicalMethod& method = canonical_method(variant);
            const std::string alone = o.out + "/alone.ply";
            io::write_ply(alone, method.run(m.V, m.F, method.settings(), context).V, m.F);
            EXPECT_EQ(io::read_file(o.out + "/" + variant + "/forms/" + model + ".ply"), io::read_file(alone))
                << variant << " " << model;
        }
    fs::remove_all(o.out);
}

TEST(Experiment, BrokenCollectionsFailPerMeshNotAsAWhole) {
    // Issue 11: a labels row naming a missing file stopped the run; a corrupt cache entry failed
    // on every re-run; classes of two models were computed in full, then "nothing to evaluate".
    const std::string data = make_collection("broken_data");
    const std::string labels = data + "/labels_broken.csv";
    io::write_file_atomic(labels, io::read_file(data + "/labels.csv") + "meshes/missing.ply,standard\n");
    auto o = options("canonform_test_experiment_broken", {"none"});
    o.dataset = data;
    o.labels = labels;
    fs::remove_all(o.out);
    std::vector<std::string> log;
    o.log = [&](const std::string& line) { log.push_back(line); };
    const auto first = retrieval::Experiment(o).run();
    EXPECT_EQ(first[0].meshes, 6u);
    EXPECT_EQ(first[0].failed, 1u);
    EXPECT_NE(io::read_file(o.out + "/none/failures.txt").find("missing: cannot read"), std::string::npos);
    // Corrupt every cache entry: each is recomputed, and said so.
    for (const auto& e : fs::directory_iterator(o.out + "/cache"))
        if (e.path().extension() == ".cfvd") io::write_file_atomic(e.path().string(), "garbage");
    log.clear();
    const auto second = retrieval::Experiment(o).run();
    EXPECT_EQ(second[0].meshes, 6u);
    EXPECT_EQ(second[0].cached, 0);
    EXPECT_EQ(std::count_if(log.begin(), log.end(),
                            [](const std::string& l) {
                                return l.find("corrupt cache entry recomputed") != std::string::npos;
                            }),
              6);
    // Two models per class: said before any work; distances written; no measures, and why.
    io::write_file_atomic(labels,
                          "path,class\nmeshes/standard_0.ply,a\nmeshes/standard_1.ply,a\n"
                          "meshes/long-arms_0.ply,b\nmeshes/long-arms_1.ply,b\n");
    log.clear();
    const auto pairs = retrieval::Experiment(o).run();
    ASSERT_FALSE(log.empty());
    EXPECT_NE(log.front().find("no class of"), std::string::npos) << log.front();
    EXPECT_NE(pairs[0].no_measures.find("no class has more than two models"), std::string::npos);
    EXPECT_EQ(io::read_distance_matrix(o.out + "/none/distances.bin").rows(), 4);
    const auto metrics = nlohmann::json::parse(io::read_file(o.out + "/none/metrics.json"));
    EXPECT_TRUE(metrics["micro"].is_null());
    EXPECT_NE(retrieval::report_markdown(o, 4, pairs, "").find("No measures for none"), std::string::npos);
    // Checked before any work: rows without a class, two models of one name.
    fs::remove_all(o.out);
    io::write_file_atomic(labels, "path,class\nmeshes/standard_0.ply,a\nmeshes/standard_1.ply,\n");
    EXPECT_THROW(retrieval::Experiment{o}, InputError);
    io::write_file_atomic(
        labels, "path,class\nmeshes/standard_0.ply,a\nother/standard_0.ply,b\nmeshes/standard_1.ply,b\n");
    EXPECT_THROW(retrieval::Experiment{o}, InputError);
    EXPECT_FALSE(fs::exists(o.out));  // nothing was started
}

TEST(Experiment, AFormWithNanCoordinatesIsAFailureNotAResult) {
    // Issue 11: retrieve kept a form with NaN coordinates. A method that breaks on two meshes (a
    // NaN coordinate) fails those two, named, and the others are evaluated.
    static std::atomic<int> calls{0};
    calls = 0;
    CanonicalMethod broken;
    broken.name = "toy-nan";
    broken.label = "toy nan";
    broken.run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi&, const MethodSettings&,
                    const MethodContext&) {
        CanonicalForm r;
        r.V = V;
        if (calls++ < 2) r.V(0, 0) = std::numeric_limits<double>::quiet_NaN();
        return r;
    };
    register_canonical_method(broken);
    auto o = options("canonform_test_experiment_nan", {"toy-nan"});
    fs::remove_all(o.out);
    const auto out = retrieval::Experiment(o).run();
    unregister_canonical_method("toy-nan");
    ASSERT_EQ(out.size(), 1u);
    const std::string failures = io::read_file(o.out + "/toy-nan/failures.txt");
    EXPECT_NE(failures.find("NaN or infinite coordinates"), std::string::npos) << failures;
    EXPECT_EQ(out[0].failed, 2u);
    EXPECT_EQ(out[0].meshes, 4u);  // the evaluated ones
    EXPECT_EQ(io::read_distance_matrix(o.out + "/toy-nan/distances.bin").rows(), 4);
    // No form with NaN is left in the run folder.
    int forms = 0;
    for (const auto& e : fs::recursive_directory_iterator(o.out)) {
        if (e.path().extension() != ".ply") continue;
        ++forms;
        EXPECT_TRUE(io::read_mesh(e.path().string()).V.allFinite()) << e.path();
    }
    EXPECT_EQ(forms, 8);  // forms/ and cache/, of the four good meshes
}

TEST(Experiment, FusedMethodSumsItsMembersNormalisedDistances) {
    auto o = options("canonform_test_experiment_fused", {"none"});
    o.dataset = make_collection("fused_data");  // its own copy: ctest runs this file's tests in parallel
    o.labels = o.dataset + "/labels.csv";
    fs::remove_all(o.out);
    o.fused.push_back(retrieval::parse_fused_spec("fused:none*0.4+euclidean-N:beta=65*0.6"));
    o.fused.push_back(retrieval::parse_fused_spec("fused-median:none*0.4+euclidean-N:beta=65*0.6"));
    const auto out = retrieval::Experiment(o).run();  // euclidean-N:beta=65 is added as a member
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[1].spec.folder(), "euclidean-N_beta65");
    EXPECT_EQ(out[2].label, "fused_none0.4+euclidean-N_beta650.6");
    const std::string dir = o.out + "/" + out[2].label;
    for (const char* f : {"/distances.bin", "/models.csv", "/metrics.json", "/pr.csv"})
        EXPECT_TRUE(io::is_file(dir + f)) << f;
    const Eigen::MatrixXf A = io::read_distance_matrix(o.out + "/none/distances.bin").cast<float>();
    const Eigen::MatrixXf B =
        io::read_distance_matrix(o.out + "/euclidean-N_beta65/distances.bin").cast<float>();
    const Eigen::MatrixXf F = io::read_distance_matrix(dir + "/distances.bin").cast<float>();
    EXPECT_TRUE(F.isApprox(retrieval::fuse_distances({A, B}, {0.4, 0.6}), 1e-5f));
    // The previous rule, by its own name and folder.
    EXPECT_EQ(out[3].label, "fused-median_none0.4+euclidean-N_beta650.6");
    const Eigen::MatrixXf M =
        io::read_distance_matrix(o.out + "/" + out[3].label + "/distances.bin").cast<float>();
    EXPECT_TRUE(M.isApprox(retrieval::fuse_distances({A, B}, {0.4, 0.6}, retrieval::FusionRule::GlobalMedian),
                           1e-5f));
    EXPECT_FALSE(M.isApprox(F, 1e-2f));
    EXPECT_EQ(out[2].meshes, 6u);
    EXPECT_EQ(out[2].evaluation.micro.queries, 6);
    const std::string report = retrieval::report_markdown(o, 6, out, "");
    EXPECT_NE(report.find("| fused_none0.4+euclidean-N_beta650.6 |"), std::string::npos);
}

namespace {
retrieval::MethodOutcome measured(const std::string& method, double nn, double ft, double st, double e,
                                  double dcg) {
    retrieval::MethodOutcome m;
    m.spec = parse_method_spec(method);
    m.evaluation.micro = {nn, ft, st, e, dcg, 10};
    return m;
}
}  // namespace

TEST(Experiment, SummaryNamesTheBestPerMeasureAndAFusedMethodThatDoesNotBeatItsMembers) {
    std::vector<retrieval::MethodOutcome> out = {measured("none", 0.90, 0.70, 0.80, 0.50, 0.85),
                                                 measured("euclidean-N", 0.95, 0.60, 0.85, 0.50, 0.80)};
    retrieval::MethodOutcome fused = measured("none", 0.96, 0.65, 0.8504, 0.55, 0.90);
    fused.label = "fused_none+euclidean-N";
    fused.members = {"none", "euclidean-N"};
    out.push_back(fused);
    const std::string s = retrieval::summary_markdown(out);
    // Ties at the shown precision name every method (E-measure of none and euclidean-N is 0.500,
    // but the fused method's 0.550 is best); 2-Tier 0.8504 shows as 0.850 and ties euclidean-N.
    EXPECT_NE(s.find("NN fused_none+euclidean-N (0.960)"), std::string::npos) << s;
    EXPECT_NE(s.find("1-Tier none (0.700)"), std::string::npos) << s;
    EXPECT_NE(s.find("2-Tier euclidean-N, fused_none+euclidean-N (0.850)"), std::string::npos) << s;
    EXPECT_NE(s.find("fused_none+euclidean-N does not beat its best member on this collection: "
                     "1-Tier 0.650 against none's 0.700; 2-Tier 0.850 ties euclidean-N's 0.850."),
              std::string::npos)
        << s;
    // Better on all five: said so, and nothing about falling behind.
    out[2].evaluation.micro = {0.96, 0.75, 0.90, 0.60, 0.90, 10};
    const std::string t = retrieval::summary_markdown(out);
    EXPECT_NE(t.find("fused_none+euclidean-N beats every member on all five measures."), std::string::npos)
        << t;
    EXPECT_EQ(t.find("does not beat"), std::string::npos) << t;
    // One measured method: nothing to compare; a member without measures: no verdict on the fusion.
    EXPECT_EQ(retrieval::summary_markdown({out[0]}), "");
    out[1].no_measures = "no class has more than two models";
    EXPECT_EQ(retrieval::summary_markdown(out).find("beats every member"), std::string::npos);
    // The report carries the summary after the table.
    retrieval::ExperimentOptions o;
    const std::string report = retrieval::report_markdown(o, 10, out, "");
    EXPECT_NE(report.find("## Summary"), std::string::npos);
    EXPECT_LT(report.find("| fused_none+euclidean-N |"), report.find("## Summary"));
}

TEST(Experiment, PoseConsistencyIsZeroForRigidOrMirroredCopiesAndIndependentOfThreads) {
    // Forms of five models in two classes, with correspondences (1-based, reversed order: the
    // k-th point of the template is vertex n - k): class a = a cloud, the cloud turned and moved,
    // and its mirror image; class b = another cloud and a copy with one coordinate stretched.
    const std::string dir = canonform::test::process_temp_path("canonform_test_pose");
    fs::remove_all(dir);
    fs::create_directories(dir + "/forms");
    fs::create_directories(dir + "/corres");
    const int n = 50;
    Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, 3), B = Eigen::MatrixXd::Random(n, 3);
    Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    Eigen::MatrixXd turned = (A * R.transpose()).rowwise() + Eigen::RowVector3d(3, -1, 2);
    Eigen::MatrixXd mirrored = A;
    mirrored.col(1) *= -1;
    Eigen::MatrixXd stretched = B;
    stretched.col(2) *= 1.5;
    const Eigen::MatrixXi F(0, 3);
    std::vector<retrieval::Model> models;
    const std::vector<std::pair<std::string, const Eigen::MatrixXd*>> forms = {
        {"a0", &A}, {"a1", &turned}, {"a2", &mirrored}, {"b0", &B}, {"b1", &stretched}};
    for (const auto& [name, V] : forms) {
        io::write_ply(dir + "/forms/" + name + ".ply", *V, F);
        std::ofstream vts(dir + "/corres/" + name + ".vts");
        for (int k = 0; k < n; ++k) vts << n - k << "\n";
        retrieval::Model m;
        m.name = name;
        m.label = name.substr(0, 1);
        models.push_back(m);
    }
    const std::vector<size_t> good = {0, 1, 2, 3, 4};
    int pairs1 = 0, pairs2 = 0;
    const double c1 = retrieval::pose_consistency(models, good, dir, dir + "/forms", &pairs1, 1);
    const double c2 = retrieval::pose_consistency(models, good, dir, dir + "/forms", &pairs2, 2);
    EXPECT_EQ(pairs1, 4);  // a0-a1, a0-a2, a1-a2, b0-b1
    EXPECT_EQ(pairs2, 4);
    EXPECT_EQ(std::memcmp(&c1, &c2, sizeof c1), 0);
    // Only b0-b1 is not a rigid motion or mirror image: its term is the RMS residual of the best
    // alignment of B to the stretched cloud over the stretched cloud's RMS radius.
    const double radius =
        std::sqrt((stretched.rowwise() - stretched.colwise().mean()).squaredNorm() / static_cast<double>(n));
    Eigen::MatrixXd Bm = B;
    Bm.col(0) *= -1;
    const double b_term =
        std::min(numerics::align_rigid(B, stretched).rms, numerics::align_rigid(Bm, stretched).rms) / radius;
    EXPECT_GT(b_term, 0.01);
    EXPECT_NEAR(c1, b_term / 4, 1e-9);
    // Without correspondences: not measured.
    fs::remove_all(dir + "/corres");
    int none = -1;
    EXPECT_EQ(retrieval::pose_consistency(models, good, dir, dir + "/forms", &none, 2), -1.0);
    EXPECT_EQ(none, 0);
    fs::remove_all(dir);
}
