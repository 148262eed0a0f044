// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the plugins as pymeshlab 2022.2, 2023.12 and 2025.7 see them, without Python.
//
// pymeshlab 2022.2.x is MeshLab 2022.02's meshlab-common in double precision behind pybind11,
// pymeshlab 2025.7.x the same of MeshLab 2025.07, pymeshlab 2023.12.x of MeshLab 2023.12 (here
// MeshLab 2025.07's source as "2023.12d", cmake/MeshLabFromSource.cmake ALSO_AS). This program links the same
// library (built from Debian's source, cmake/MeshLabFromSource.cmake; one build of this program per release)
// and makes the calls pymeshlab's Python calls make, through canonform::meshlab::MeshSet
// (filter_canonical/meshlab_meshset.h, which the canonform-meshlab runner shares):
//   pymeshlab.load_plugin(path), ms.add_mesh(...), ms.apply_filter(name, **kwargs).
// It applies every filter of both plugins by its Python name with Python-style keywords on a
// generated figure and checks the results, and checks that a plugin compiled for the other
// precision is refused with MeshLab's message. Results go to OUT for the comparison with the other
// builds (tests/e2e/same_results_test.sh).
//
//   canonform_pymeshlab<YYYY>_harness --plugin P.so [--plugin P2.so ...] [--wrong-precision W.so]
//       [--wrong-version W.so]... [--vertices N] [--pose K] [--codebook CB] --out DIR
//   canonform_pymeshlab<YYYY>_harness --serve
// --serve answers one JSON request per line on stdin (load_plugin, load_new_mesh, mesh_number,
// set_current_mesh, apply_filter) with one JSON line on stdout: the back end of the stand-in
// pymeshlab module with which tests/readme_pymeshlab_test.py runs the README's examples as written.
#include "canonform/io/mesh_io.h"
#include "canonform/meshlab/meshlab_meshset.h"
#include "canonform/procedural/procedural_meshes.h"

#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include <common/globals.h>
#include <common/python/function_set.h>
#include <common/utilities/eigen_mesh_conversions.h>

#include <QDir>
#include <QFileInfo>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

using canonform::meshlab::Dict;
using canonform::meshlab::Kwargs;
using canonform::meshlab::load_plugin;
using canonform::meshlab::MeshSet;

namespace {

// --- checks --------------------------------------------------------------------------------------

int passes = 0, failures = 0;

void check(bool ok, const std::string& what) {
    std::printf("  %s %s\n", ok ? "ok  " : "FAIL", what.c_str());
    std::fflush(stdout);
    (ok ? passes : failures)++;
}

/// The message of the MLException that `f` throws, or "" (and a failed check) if none.
template <class F>
std::string error_of(F&& f, const std::string& what) {
    try {
        f();
    } catch (const MLException& e) {
        return e.what();
    } catch (const std::exception& e) {
        check(false, what + ": threw a non-MLException: " + e.what());
        return "";
    }
    check(false, what + ": no exception");
    return "";
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

/// The MeshLab parameter class a table parameter is shown as (meshlab_adapter_common.h).
std::string meshlab_type(const canonform::Parameter& p) {
    switch (p.type()) {
        case canonform::ParameterType::Bool:
            return "RichBool";
        case canonform::ParameterType::Int:
            return "RichInt";
        case canonform::ParameterType::Float:
            return "RichFloat";
        case canonform::ParameterType::Choice:
            return "RichEnum";
        case canonform::ParameterType::Text:
            return "RichString";
    }
    return "";
}

bool is_int(const Dict& d, const char* k) {
    return d.count(k) && std::string(d.at(k).typeName()) == "int";
}
bool is_double(const Dict& d, const char* k) {
    return d.count(k) && std::string(d.at(k).typeName()) == "double";
}
bool is_bool(const Dict& d, const char* k) {
    return d.count(k) && std::string(d.at(k).typeName()) == "bool";
}
bool is_vector(const Dict& d, const char* k) {
    return d.count(k) && d.at(k).canConvert<Eigen::VectorXd>();
}

/// Writes the mesh `m` (positions, faces, vertex quality) as an ASCII PLY with 9 significant
/// digits, the input of the MeshLab 2020.09 comparison.
void write_ply(const std::string& path, const CMeshO& m, bool quality) {
    const EigenMatrixX3m V = meshlab::vertexMatrix(m);
    const Eigen::MatrixX3i F = meshlab::faceMatrix(m);
    const EigenVectorXm Q = quality ? meshlab::vertexQualityArray(m) : EigenVectorXm();
    std::ofstream o(path);
    // Double precision, as the tool writes (17 significant digits round-trip a double exactly).
    o << "ply\nformat ascii 1.0\nelement vertex " << V.rows()
      << "\nproperty double x\nproperty double y\nproperty double z\n";
    if (quality) o << "property double quality\n";
    o << "element face " << F.rows() << "\nproperty list uchar int vertex_indices\nend_header\n"
      << std::setprecision(17);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
        o << V(i, 0) << " " << V(i, 1) << " " << V(i, 2);
        if (quality) o << " " << Q(i);
        o << "\n";
    }
    for (Eigen::Index i = 0; i < F.rows(); ++i)
        o << "3 " << F(i, 0) << " " << F(i, 1) << " " << F(i, 2) << "\n";
    if (!o) throw std::runtime_error("cannot write " + path);
}

MeshModel* layer_named(MeshSet& ms, const QString& label) {
    for (MeshModel& m : ms.meshIterator())
        if (m.label() == label) return &m;
    return nullptr;
}

/// --serve: one JSON request per line, one JSON answer per line ({"error": message} on failure).
int serve() {
    MeshSet ms;
    std::string line;
    while (std::getline(std::cin, line)) {
        nlohmann::json answer = nlohmann::json::object();
        try {
            const nlohmann::json r = nlohmann::json::parse(line);
            const std::string op = r.at("op");
            if (op == "load_plugin") {  // answers the seconds it took (bench/portable_bench.sh)
                const auto t0 = std::chrono::steady_clock::now();
                load_plugin(r.at("path"));
                answer["seconds"] =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            } else if (op == "load_new_mesh") {  // pymeshlab reads it with its IO plugin; here our reader
                const std::string path = r.at("path");
                const canonform::Mesh m = canonform::io::read_mesh(path);
                ms.add_mesh(m.V, m.F, QFileInfo(QString::fromStdString(path)).fileName());
            } else if (op == "mesh_number") {
                answer["value"] = ms.meshNumber();
            } else if (op == "set_current_mesh") {
                const int id = r.at("id");
                if (ms.getMesh(static_cast<unsigned>(id)) == nullptr)
                    throw MLException("Mesh with id " + QString::number(id) + " does not exist.");
                ms.setCurrentMesh(id);
            } else if (op == "apply_filter") {
                Kwargs kwargs;
                for (const auto& [k, v] : r.at("kwargs").items()) {
                    if (v.is_boolean())
                        kwargs.emplace_back(k, v.get<bool>());
                    else if (v.is_number_integer())
                        kwargs.emplace_back(k, v.get<int>());
                    else if (v.is_number())
                        kwargs.emplace_back(k, v.get<double>());
                    else
                        kwargs.emplace_back(k, v.get<std::string>());
                }
                answer["value"] =
                    nlohmann::json::parse(canonform::meshlab::to_json(ms.apply_filter(r.at("name"), kwargs)));
            } else {
                throw MLException(QString::fromStdString("unknown request " + op));
            }
        } catch (const std::exception& e) {
            answer = {{"error", e.what()}};
        }
        std::cout << answer.dump() << std::endl;
    }
    return 0;
}

int usage() {
    std::fprintf(stderr,
                 "usage: canonform_pymeshlab_harness --plugin P.so [--plugin ...] [--wrong-precision W.so]\n"
                 "       [--wrong-version W.so] [--vertices N] [--pose K] [--codebook CB] --out DIR\n"
                 "       canonform_pymeshlab_harness --serve\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> plugins, wrong_versions;
    std::string wrong, out, codebook;
    int vertices = 2500, pose = 4;
    if (argc == 2 && std::string(argv[1]) == "--serve") return serve();
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) return usage();
        if (a == "--plugin")
            plugins.push_back(argv[++i]);
        else if (a == "--wrong-precision")
            wrong = argv[++i];
        else if (a == "--wrong-version")
            wrong_versions.push_back(argv[++i]);
        else if (a == "--vertices")
            vertices = std::atoi(argv[++i]);
        else if (a == "--pose")
            pose = std::atoi(argv[++i]);
        else if (a == "--codebook")
            codebook = argv[++i];
        else if (a == "--out")
            out = argv[++i];
        else
            return usage();
    }
    if (plugins.empty() || out.empty()) return usage();
    QDir().mkpath(QString::fromStdString(out));
    std::ofstream json(out + "/outputs.json");
    json << "{";
    auto record = [&json, first = true](const std::string& name, const Dict& d) mutable {
        json << (first ? "" : ",\n ") << "\"" << name << "\": " << canonform::meshlab::to_json(d, true);
        first = false;
    };

    const std::string release = meshlab::meshlabVersion().substr(0, 7);  // "2022.02", "2023.12", "2025.07"
    std::printf("MeshLab %s (built with %s precision), pymeshlab %s's plugin loading\n",
                meshlab::meshlabVersion().c_str(), meshlab::builtWithDoublePrecision() ? "double" : "single",
                release == "2022.02"   ? "2022.2"
                : release == "2023.12" ? "2023.12"
                                       : "2025.7");
    try {
        // 1. A plugin of the wrong precision is refused, with MeshLab's reason ---------------------
        if (!wrong.empty()) {
            const std::string msg =
                error_of([&] { load_plugin(wrong); }, "load_plugin(other-precision plugin)");
            std::printf("  load_plugin('%s') -> MLException: %s\n", wrong.c_str(), msg.c_str());
            check(contains(msg, "has different floating point precision from the running MeshLab version"),
                  "a plugin built for single precision (a float MeshLab's) is refused: 'different floating "
                  "point precision'");
        }
        // ... and those of the other pymeshlab releases (same precision, other version prefix)
        for (const std::string& wrong_version : wrong_versions) {
            const std::string msg =
                error_of([&] { load_plugin(wrong_version); }, "load_plugin(other release's plugin)");
            std::printf("  load_plugin('%s') -> MLException: %s\n", wrong_version.c_str(), msg.c_str());
            check(contains(msg, "has different version from the running MeshLab version"),
                  "the plugin built for the other pymeshlab release is refused: 'different version'");
        }
        // 2. load_plugin on each plugin ---------------------------------------------------------
        for (const auto& p : plugins) {
            bool loaded = true;
            try {
                load_plugin(p);
            } catch (const std::exception& e) {
                loaded = false;
                std::printf("  load_plugin('%s') -> %s\n", p.c_str(), e.what());
            }
            check(loaded,
                  "load_plugin(" + QFileInfo(QString::fromStdString(p)).fileName().toStdString() + ")");
        }
        if (!plugins.empty()) {
            const std::string again = error_of([&] { load_plugin(plugins[0]); }, "load_plugin twice");
            check(contains(again, "has been already loaded"),
                  "loading the same plugin twice is refused: " + again);
        }
        const pymeshlab::FunctionSet& fs = pymeshlab::functionSetInstance();
        // Every filter of both tables by its Python name, with the table's keywords and MeshLab
        // types in the table's order (the expected lists are the tables: canonical_filter_table.cpp,
        // view_filter_table.cpp; what the names must never lose is tests/test_filter_table.cpp's).
        std::vector<const canonform::meshlab::FilterSpec*> specs;
        for (const auto& f : canonform::meshlab::filter_table()) specs.push_back(&f);
        for (const auto& f : canonform::meshlab::view_filter_table()) specs.push_back(&f);
        for (const canonform::meshlab::FilterSpec* spec : specs) {
            const QString name = QString::fromStdString(spec->python_name);
            const bool has = fs.containsFilterFunction(name);
            std::string problems;
            if (has) {
                const auto& f = fs.filterFunction(name);
                const QStringList order = f.pythonFunctionParameters();
                for (size_t k = 0; k < spec->params.size(); ++k) {
                    const canonform::Parameter& p = spec->params[k];
                    const QString pn = QString::fromStdString(p.name());
                    if (!f.contains(pn)) {
                        problems += " " + p.name() + " missing";
                        continue;
                    }
                    const std::string type =
                        f.getFilterFunctionParameter(pn).meshlabTypeString().toStdString();
                    if (type != meshlab_type(p)) problems += " " + p.name() + " is " + type;
                    if (static_cast<int>(k) >= order.size() || order[static_cast<int>(k)] != pn)
                        problems += " " + p.name() + " out of order";
                }
                if (f.parametersNumber() != spec->params.size())
                    problems += " (" + std::to_string(f.parametersNumber()) + " parameters)";
            }
            check(has && problems.empty(),
                  "Python name " + spec->python_name + " with the " + std::to_string(spec->params.size()) +
                      " keywords and types of the table" + (problems.empty() ? "" : ":" + problems));
        }

        // 3. Every filter by its Python name on a generated figure ------------------------------
        // The figure of 'canonform generate OUT --vertices N --pose K': coordinates rounded to float.
        const canonform::procedural::Figure fig =
            canonform::procedural::make_figure(vertices, canonform::procedural::figure_pose(pose));
        const Eigen::MatrixXd V = fig.mesh.V.cast<float>().cast<double>();
        const long n = V.rows();
        const int sqrt_n = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
        MeshSet ms;
        ms.add_mesh(V, fig.mesh.F, "fig.ply");
        write_ply(out + "/input.ply", ms.mm()->cm, false);
        std::printf("  figure: %ld vertices, %ld faces (pose %d)\n", n, long(fig.mesh.F.rows()), pose);

        // compute_conformal_factor
        Dict cf = ms.apply_filter("compute_conformal_factor", {{"normalize", true}, {"colorize", false}});
        record("compute_conformal_factor", cf);
        const EigenVectorXm q = meshlab::vertexQualityArray(ms.mm()->cm);
        check(is_int(cf, "vertices") && cf["vertices"].toInt() == n && is_double(cf, "min") &&
                  is_double(cf, "max") && cf["min"].toDouble() < cf["max"].toDouble() &&
                  is_double(cf, "residual") && cf["residual"].toDouble() < 1e-6,
              "compute_conformal_factor: dict {vertices: int, min, max, residual: float}");
        check(q.size() == n && q.minCoeff() == 0 && std::abs(q.maxCoeff() - 1) < 1e-12,
              "compute_conformal_factor(normalize=True): vertex quality spans [0, 1]");
        write_ply(out + "/cf.ply", ms.mm()->cm, true);
        Dict cf_raw = ms.apply_filter("compute_conformal_factor", {{"normalize", false}, {"colorize", true}});
        const EigenVectorXm q_raw = meshlab::vertexQualityArray(ms.mm()->cm);
        check(std::abs(q_raw.minCoeff() - cf_raw["min"].toDouble()) < 1e-9 &&
                  std::abs(q_raw.maxCoeff() - cf_raw["max"].toDouble()) < 1e-9 &&
                  ms.mm()->hasDataMask(MeshModel::MM_VERTCOLOR),
              "compute_conformal_factor(normalize=False, colorize=True): raw quality = dict's range, colours "
              "on");

        // compute_feature_points (variant A's fill: exactly ceil(sqrt(N)) points)
        const size_t layers0 = ms.meshNumber();
        Dict fp =
            ms.apply_filter("compute_feature_points",
                            {{"ring", 2}, {"fill", std::string("random")}, {"seed", 3}, {"add_layer", true}});
        record("compute_feature_points", fp);
        const long selected = (meshlab::vertexSelectionArray(ms.mm()->cm).array()).count();
        check(is_int(fp, "selected") && fp["selected"].toInt() == sqrt_n && selected == sqrt_n &&
                  ms.mm()->cm.svn == sqrt_n,
              "compute_feature_points(fill='random'): " + std::to_string(selected) +
                  " selected = ceil(sqrt(" + std::to_string(n) + ")) = " + std::to_string(sqrt_n));
        const MeshModel* points = layer_named(ms, "fig feature points");
        check(ms.meshNumber() == layers0 + 1 && points && points->cm.vn == sqrt_n && points->cm.fn == 0,
              "compute_feature_points(add_layer=True): layer 'fig feature points' with those points");
        Dict fp_none = ms.apply_filter("compute_feature_points", {{"fill", 0}, {"add_layer", false}});
        check(fp_none["random"].toInt() == 0 && fp_none["selected"].toInt() == fp_none["maxima"].toInt() &&
                  fp_none["selected"].toInt() <= sqrt_n && ms.meshNumber() == layers0 + 1,
              "compute_feature_points(fill=0): the maxima only (enum by index), no new layer");

        // generate_euclidean_canonical_form, variant N (default) and A, in new layers
        Dict ecf = ms.apply_filter("generate_euclidean_canonical_form",
                                   {{"variant", std::string("N")}, {"alpha", 10.0}, {"new_layer", true}});
        record("generate_euclidean_canonical_form", ecf);
        MeshModel* canon = layer_named(ms, "fig canonical form");
        check(canon && canon->cm.vn == n && canon->cm.fn == fig.mesh.F.rows(),
              "generate_euclidean_canonical_form: layer 'fig canonical form' with the input's vertices and "
              "faces");
        check(is_int(ecf, "iterations") && ecf["iterations"].toInt() > 0 &&
                  is_double(ecf, "initial_stress") && is_double(ecf, "final_stress") &&
                  ecf["final_stress"].toDouble() < ecf["initial_stress"].toDouble() &&
                  ecf["final_stress"].toDouble() > 0 && is_bool(ecf, "converged") &&
                  ecf["converged"].toBool() && is_double(ecf, "mean_relative_edge_change") &&
                  ecf["mean_relative_edge_change"].toDouble() > 0 &&
                  ecf["mean_relative_edge_change"].toDouble() < 0.5 && ecf["beta"].toDouble() == 130,
              "generate_euclidean_canonical_form: dict iterations " +
                  ecf["iterations"].toString().toStdString() + ", stress " +
                  ecf["initial_stress"].toString().toStdString() + " -> " +
                  ecf["final_stress"].toString().toStdString() + ", converged, beta 130");
        if (canon) {
            const long canon_selected = meshlab::vertexSelectionArray(canon->cm).count();
            check(canon_selected == ecf["feature_points"].toInt(),
                  "generate_euclidean_canonical_form: feature points selected");
            const double moved = (meshlab::vertexMatrix(canon->cm) - V).rowwise().norm().maxCoeff();
            check(moved > 1e-3, "generate_euclidean_canonical_form: the layer is not the input pose");
            write_ply(out + "/canon.ply", canon->cm, true);
        }
        Dict ecf_a = ms.apply_filter("generate_euclidean_canonical_form",
                                     {{"variant", 0}, {"seed", 5}, {"new_layer", true}});
        record("generate_euclidean_canonical_form_A", ecf_a);
        check(ecf_a["feature_points"].toInt() == sqrt_n && ecf_a["beta"].toDouble() == 10,
              "generate_euclidean_canonical_form(variant=0 i.e. A): ceil(sqrt(N)) feature points, beta 10");

        // generate_geodesic_canonical_form (classical MDS), and its refusal over the memory limit
        const size_t layers1 = ms.meshNumber();
        Dict geo =
            ms.apply_filter("generate_geodesic_canonical_form", {{"method", std::string("classical")}});
        record("generate_geodesic_canonical_form", geo);
        check(ms.meshNumber() == layers1 + 1 && is_double(geo, "mds_seconds") &&
                  is_double(geo, "geodesic_seconds") && is_double(geo, "mean_relative_edge_change"),
              "generate_geodesic_canonical_form(method='classical'): new layer, timings and edge change in "
              "the dict");
        const std::string refused = error_of(
            [&] {
                ms.apply_filter("generate_geodesic_canonical_form", {{"max_memory_gib", 0.001}});
            },
            "geodesic refusal");
        check(contains(refused, "Failed to apply filter: generate_geodesic_canonical_form") &&
                  contains(refused, "needs about") && ms.meshNumber() == layers1 + 1,
              "generate_geodesic_canonical_form(max_memory_gib=0.001): MLException naming memory and time, "
              "no layer");

        // compute_depth_view_descriptor: the descriptor as a vector (numpy array in pymeshlab)
        const std::string dfile = out + "/descriptor.cfvd";
        Kwargs dk = {{"output_file", dfile}, {"seed", 0}};
        if (!codebook.empty()) dk.push_back({"codebook_file", codebook});
        Dict dv = ms.apply_filter("compute_depth_view_descriptor", dk);
        record("compute_depth_view_descriptor", dv);
        const Eigen::VectorXd per_view = dv["keypoints_per_view"].value<Eigen::VectorXd>();
        const Eigen::VectorXd desc = dv["descriptor"].value<Eigen::VectorXd>();
        check(is_int(dv, "views") && dv["views"].toInt() == 66 && is_vector(dv, "keypoints_per_view") &&
                  per_view.size() == 66 && per_view.sum() == dv["keypoints"].toInt() &&
                  dv["keypoints"].toInt() > 66,
              "compute_depth_view_descriptor: 66 views, keypoints_per_view a vector of 66 summing to "
              "keypoints (" +
                  dv["keypoints"].toString().toStdString() + ")");
        const int words = dv["codebook_words"].toInt();
        const bool desc_ok = is_vector(dv, "descriptor") &&
                             (words > 0 ? desc.size() == 66L * words && desc.sum() == per_view.sum()
                                        : desc.size() == static_cast<Eigen::Index>(per_view.sum()) * 128);
        check(desc_ok && desc.size() > 0 && QFileInfo::exists(QString::fromStdString(dfile)),
              "compute_depth_view_descriptor: descriptor vector of " + std::to_string(desc.size()) +
                  " values (" +
                  (words > 0 ? "66 histograms of " + std::to_string(words) + " words"
                             : std::string("raw SIFT, 128 per keypoint")) +
                  "), file written");
        Dict dv_nofile = ms.apply_filter("compute_depth_view_descriptor",
                                         {{"output_file", std::string()}, {"image_size", 128}});
        check(dv_nofile["descriptor"].value<Eigen::VectorXd>().size() > 0,
              "compute_depth_view_descriptor(output_file=''): vector only");

        // 4. Errors are MLExceptions with the reason ------------------------------------------------
        const std::string bad_enum = error_of(
            [&] {
                ms.apply_filter("generate_euclidean_canonical_form", {{"variant", std::string("Z")}});
            },
            "bad enum");
        check(contains(bad_enum, "Enum 'Z' not found. Possible values are 'A'; 'N';"),
              "variant='Z': " + bad_enum);
        const std::string bad_kw = error_of(
            [&] {
                ms.apply_filter("compute_conformal_factor", {{"normalise", true}});
            },
            "bad keyword");
        check(contains(bad_kw, "Parameter normalise not found"), "unknown keyword: " + bad_kw);
        MeshSet cloud;
        cloud.add_mesh(V.topRows(100), Eigen::MatrixXi(0, 3), "cloud.ply");
        const std::string bad_mesh =
            error_of([&] { cloud.apply_filter("generate_euclidean_canonical_form", {}); }, "point cloud");
        std::printf("  on a point cloud -> MLException: %s\n", bad_mesh.c_str());
        check(contains(bad_mesh, "Failed to apply filter: generate_euclidean_canonical_form") &&
                  contains(bad_mesh, "Euclidean canonical form: ") && contains(bad_mesh, "point cloud") &&
                  cloud.meshNumber() == 1,
              "a point cloud: MLException with the reason, no new layer");
        // A mesh with two duplicate faces and an unreferenced vertex (issue 11): refused by
        // default with the reason, document unchanged; repair=True repairs the document and runs.
        Eigen::MatrixXd Vd(V.rows() + 1, 3);
        Vd << V, Eigen::RowVector3d(9, 9, 9);
        Eigen::MatrixXi Fd(fig.mesh.F.rows() + 2, 3);
        Fd << fig.mesh.F, fig.mesh.F.row(0), fig.mesh.F.row(1);
        MeshSet dup;
        dup.add_mesh(Vd, Fd, "dup.ply");
        const std::string strict =
            error_of([&] { dup.apply_filter("compute_conformal_factor", {}); }, "unrepaired mesh");
        check(
            contains(strict, "non-manifold") && dup.mm()->cm.fn == Fd.rows() && dup.mm()->cm.vn == Vd.rows(),
            "duplicate faces: MLException with the reason, mesh unchanged: " + strict.substr(0, 120));
        Dict fixed = dup.apply_filter("compute_conformal_factor", {{"repair", true}});
        check(dup.mm()->cm.fn == fig.mesh.F.rows() && dup.mm()->cm.vn == V.rows() &&
                  is_double(fixed, "residual"),
              "repair=True: the 2 duplicate faces and the unreferenced vertex removed from the document, "
              "then computed");
    } catch (const std::exception& e) {
        check(false, std::string("unexpected exception: ") + e.what());
    }
    json << "}\n";
    std::printf("%d passed, %d failed\n", passes, failures);
    return failures == 0 ? 0 : 1;
}
