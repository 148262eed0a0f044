// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark of SMACOF's accelerations (numerics/smacof.h) side by side in one run:
//   canonform_bench_acceleration [--sizes 2000,10000,...] [--poses P] [--repeats R] [--variant N|A]
//                                [--methods none,relaxed,rre,mpe,anderson] [--depth K]
//                                [--dataset DIR --labels FILE --name NAME]... [--geodesic N] [--csv FILE]
// For every procedural size (figures in poses 0..P-1, corresponding vertex by vertex) and every
// dataset (TOSCA, FAUST: off/*.off with labels.csv and corres/*.vts), the Euclidean canonical form
// of every mesh with every acceleration, the methods interleaved per mesh so that they see the same
// machine load: Guttman steps (every stress evaluation), seconds (SMACOF and whole computation;
// median of R runs per mesh), final stress relative to the plain run's (max and mean over meshes),
// aligned RMS distance to the plain run's form (relative to its RMS radius) and pose consistency
// (mean over same-class / same-figure pairs of the aligned RMS distance between corresponding
// vertices, relative to the RMS radius, as retrieval/experiment.h measures it). --geodesic N adds
// least-squares MDS of the all-pairs geodesic distances of an N-vertex figure (the geodesic
// canonical form's step 3). Prints a markdown table, writes one CSV row per (set, method).
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/common/heap_pages.h"
#include "canonform/io/mesh_io.h"
#include "canonform/numerics/mds.h"
#include "canonform/numerics/rigid_alignment.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/geodesic_distances.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace canonform;
using namespace canonform::numerics;
using namespace canonform::surface;
using namespace canonform::canonical;
using namespace canonform::procedural;

namespace {

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string part;
    while (std::getline(in, part, ',')) out.push_back(part);
    return out;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n == 0 ? 0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

double rms_radius(const Eigen::MatrixXd& Q) {
    return std::sqrt((Q.rowwise() - Q.colwise().mean()).squaredNorm() / static_cast<double>(Q.rows()));
}

/// Aligned RMS distance of P to Q (rigid motion or mirror image) relative to Q's RMS radius.
double aligned_distance(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q) {
    Eigen::MatrixXd M = P;
    M.col(0) *= -1;
    return std::min(align_rigid(P, Q).rms, align_rigid(M, Q).rms) / rms_radius(Q);
}

struct Mesh1 {
    std::string name, label;
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
};

/// What one method did over one set of meshes.
struct Tally {
    std::vector<double> iterations, seconds, smacof_seconds, stress_ratio, to_plain;
    int extrapolations = 0, rejections = 0, unconverged = 0;
    double pose_consistency = -1;
    double conformal_seconds = 0, setup_seconds = 0;  // medians, for "where the time goes"
    std::vector<double> cf_s, setup_s;
};

struct Row {
    std::string set;
    int vertices = 0, meshes = 0;
    std::string method;
    Tally t;
};

}  // namespace

int main(int argc, char** argv) {
    canonform::advise_heap_huge_pages();  // as the tool does (common/heap_pages.h)
    std::vector<int> sizes;
    std::vector<std::string> methods = smacof_acceleration_names();
    std::vector<std::string> datasets, labels, names;
    int poses = 6, repeats = 3, depth = kDefaultAccelerationDepth, geodesic = 0;
    std::string variant = "N", csv;
    for (int k = 1; k + 1 < argc; k += 2) {
        const std::string a = argv[k], v = argv[k + 1];
        if (a == "--sizes") {
            for (const auto& s : split(v)) sizes.push_back(std::atoi(s.c_str()));
        } else if (a == "--poses") {
            poses = std::max(1, std::atoi(v.c_str()));
        } else if (a == "--repeats") {
            repeats = std::max(1, std::atoi(v.c_str()));
        } else if (a == "--variant") {
            variant = v;
        } else if (a == "--methods") {
            methods = split(v);
        } else if (a == "--depth") {
            depth = std::atoi(v.c_str());
        } else if (a == "--dataset") {
            datasets.push_back(v);
        } else if (a == "--labels") {
            labels.push_back(v);
        } else if (a == "--name") {
            names.push_back(v);
        } else if (a == "--geodesic") {
            geodesic = std::atoi(v.c_str());
        } else if (a == "--csv") {
            csv = v;
        } else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }
    if (std::find(methods.begin(), methods.end(), "none") == methods.end())
        methods.insert(methods.begin(), "none");
    try {
        EuclideanCanonicalFormOptions base;
        base.variant = variant == "A" ? CanonicalVariant::A : CanonicalVariant::N;
        base.smacof.acceleration_depth = depth;
        std::vector<Row> rows;

        // One set of meshes: every method on every mesh, interleaved; forms kept for the measures.
        const auto run_set = [&](const std::string& set, const std::vector<Mesh1>& meshes, int reps,
                                 const std::string& dataset) {
            std::map<std::string, Tally> tallies;
            std::map<std::string, std::vector<Eigen::MatrixXd>> forms;
            for (size_t m = 0; m < meshes.size(); ++m) {
                std::map<std::string, std::vector<double>> secs, smacof_secs, cf_secs, setup_secs;
                std::map<std::string, EuclideanCanonicalFormResult> results;
                for (int r = 0; r < reps; ++r)
                    for (const auto& name : methods) {
                        EuclideanCanonicalFormOptions o = base;
                        o.smacof.acceleration = parse_smacof_acceleration(name);
                        EuclideanCanonicalFormResult e =
                            euclidean_canonical_form(meshes[m].V, meshes[m].F, o);
                        secs[name].push_back(e.seconds);
                        smacof_secs[name].push_back(e.smacof_seconds);
                        cf_secs[name].push_back(e.conformal_factor_seconds);
                        setup_secs[name].push_back(e.setup_seconds);
                        if (r == 0) results[name] = std::move(e);
                    }
                const EuclideanCanonicalFormResult& plain = results["none"];
                for (const auto& name : methods) {
                    Tally& t = tallies[name];
                    const EuclideanCanonicalFormResult& e = results[name];
                    t.iterations.push_back(e.iterations);
                    t.seconds.push_back(median(secs[name]));
                    t.smacof_seconds.push_back(median(smacof_secs[name]));
                    t.cf_s.push_back(median(cf_secs[name]));
                    t.setup_s.push_back(median(setup_secs[name]));
                    t.stress_ratio.push_back(e.final_stress / plain.final_stress);
                    t.to_plain.push_back(aligned_distance(e.V, plain.V));
                    t.extrapolations += e.extrapolations;
                    t.rejections += e.rejections;
                    t.unconverged += e.converged ? 0 : 1;
                    forms[name].push_back(e.V);
                }
                std::fprintf(stderr, "%s: %s done\n", set.c_str(), meshes[m].name.c_str());
            }
            for (const auto& name : methods) {
                Tally& t = tallies[name];
                if (dataset.empty()) {  // procedural: all meshes are one figure in different poses
                    double sum = 0;
                    int pairs = 0;
                    for (size_t a = 0; a < meshes.size(); ++a)
                        for (size_t b = a + 1; b < meshes.size(); ++b, ++pairs)
                            sum += aligned_distance(forms[name][a], forms[name][b]);
                    t.pose_consistency = pairs ? sum / pairs : -1;
                } else {  // the collection's correspondences, as `retrieve` measures them
                    const std::string dir =
                        "/tmp/canonform_bench_acceleration/" + set + "/" + name + "/forms";
                    std::filesystem::create_directories(dir);
                    std::vector<retrieval::Model> models;
                    std::vector<size_t> good;
                    for (size_t m = 0; m < meshes.size(); ++m) {
                        io::write_ply(dir + "/" + meshes[m].name + ".ply", forms[name][m], meshes[m].F);
                        retrieval::Model md;
                        md.name = meshes[m].name;
                        md.label = meshes[m].label;
                        models.push_back(md);
                        good.push_back(m);
                    }
                    int pairs = 0;
                    t.pose_consistency = retrieval::pose_consistency(models, good, dataset, dir, &pairs);
                }
                Row row;
                row.set = set;
                row.vertices = static_cast<int>(meshes.front().V.rows());
                row.meshes = static_cast<int>(meshes.size());
                row.method = name;
                row.t = t;
                rows.push_back(row);
            }
        };

        for (int n : sizes) {
            std::vector<Mesh1> meshes;
            for (int p = 0; p < poses; ++p) {
                Figure f = make_figure(n, figure_pose(p));
                meshes.push_back({"pose" + std::to_string(p), "figure", f.mesh.V, f.mesh.F});
            }
            run_set("procedural-" + std::to_string(n) + (variant == "A" ? "-A" : ""), meshes, repeats, "");
        }
        for (size_t d = 0; d < datasets.size(); ++d) {
            std::vector<Mesh1> meshes;
            for (const auto& md :
                 retrieval::read_collection(datasets[d], d < labels.size() ? labels[d] : "")) {
                const Mesh m = io::read_mesh(md.path);
                meshes.push_back({md.name, md.label, m.V, m.F});
            }
            run_set(d < names.size() ? names[d] : "dataset" + std::to_string(d), meshes, 1, datasets[d]);
        }
        if (geodesic > 0) {
            const Figure f = make_figure(geodesic, figure_pose(1));
            const Eigen::MatrixXd V = normalize_scale(f.mesh.V);
            GeodesicOptions g;
            const Eigen::MatrixXd D = all_pairs_geodesic_distances(V, f.mesh.F, g);
            MdsOptions mo;
            mo.check_input = false;
            mo.smacof.acceleration_depth = depth;
            std::map<std::string, std::vector<double>> secs;
            std::map<std::string, MdsResult> results;
            for (int r = 0; r < repeats; ++r)
                for (const auto& name : methods) {
                    mo.smacof.acceleration = parse_smacof_acceleration(name);
                    const auto t0 = std::chrono::steady_clock::now();
                    MdsResult m = mds(D, MdsMethod::LeastSquares, mo);
                    secs[name].push_back(
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                    if (r == 0) results[name] = std::move(m);
                }
            for (const auto& name : methods) {
                Row row;
                row.set = "geodesic-ls-mds-" + std::to_string(geodesic);
                row.vertices = geodesic;
                row.meshes = 1;
                row.method = name;
                const MdsResult& m = results[name];
                row.t.iterations = {static_cast<double>(m.iterations)};
                row.t.seconds = row.t.smacof_seconds = {median(secs[name])};
                row.t.cf_s = row.t.setup_s = {0};
                row.t.stress_ratio = {m.final_stress / results["none"].final_stress};
                row.t.to_plain = {aligned_distance(m.X, results["none"].X)};
                row.t.extrapolations = m.extrapolations;
                row.t.rejections = m.rejections;
                row.t.unconverged = m.converged ? 0 : 1;
                rows.push_back(row);
            }
        }

        // Report: per set, each method against none (totals over the set's meshes).
        std::printf(
            "| set | vertices | meshes | acceleration | Guttman steps (median, total) | steps x | SMACOF s "
            "(total) | whole s (total) | time x | final stress / none (mean, max) | RMS to none | pose "
            "consistency | extrapolations accepted / rejected |\n|---|---|---|---|---|---|---|---|---|---|---"
            "|---|---|\n");
        std::ofstream out;
        if (!csv.empty()) {
            out.open(csv);
            out << "set,vertices,meshes,variant,depth,acceleration,median_steps,total_steps,smacof_seconds,"
                   "seconds,"
                   "conformal_seconds,setup_seconds,mean_stress_ratio,max_stress_ratio,max_rms_to_none,"
                   "pose_consistency,extrapolations,rejections,unconverged\n";
        }
        for (const Row& r : rows) {
            const Row* none = nullptr;
            for (const Row& q : rows)
                if (q.set == r.set && q.method == "none") none = &q;
            const auto sum = [](const std::vector<double>& v) {
                double s = 0;
                for (double x : v) s += x;
                return s;
            };
            const double steps = sum(r.t.iterations), secs = sum(r.t.seconds), sm = sum(r.t.smacof_seconds);
            double mean_ratio = sum(r.t.stress_ratio) / static_cast<double>(r.t.stress_ratio.size());
            const double max_ratio = *std::max_element(r.t.stress_ratio.begin(), r.t.stress_ratio.end());
            const double max_rms = *std::max_element(r.t.to_plain.begin(), r.t.to_plain.end());
            std::printf(
                "| %s | %d | %d | %s | %.0f, %.0f | %.2f | %.3f | %.3f | %.2f | %.5f, %.5f | %.4f | %s | %d "
                "/ %d%s |\n",
                r.set.c_str(), r.vertices, r.meshes, r.method.c_str(), median(r.t.iterations), steps,
                sum(none->t.iterations) / steps, sm, secs, sum(none->t.seconds) / secs, mean_ratio, max_ratio,
                max_rms,
                r.t.pose_consistency < 0 ? "-" : std::to_string(r.t.pose_consistency).substr(0, 6).c_str(),
                r.t.extrapolations, r.t.rejections,
                r.t.unconverged ? (" (" + std::to_string(r.t.unconverged) + " at the cap)").c_str() : "");
            if (out)
                out << r.set << "," << r.vertices << "," << r.meshes << "," << variant << "," << depth << ","
                    << r.method << "," << median(r.t.iterations) << "," << steps << "," << sm << "," << secs
                    << "," << sum(r.t.cf_s) << "," << sum(r.t.setup_s) << "," << mean_ratio << ","
                    << max_ratio << "," << max_rms << "," << r.t.pose_consistency << "," << r.t.extrapolations
                    << "," << r.t.rejections << "," << r.t.unconverged << "\n";
        }
        std::fflush(stdout);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
