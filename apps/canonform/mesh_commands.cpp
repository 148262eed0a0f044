// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the commands on one mesh - check, conformal, features, canonical, simplify,
// generate (picture: picture_command.cpp).
#include "cli.h"

#include "canonform/canonical/method_registry.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/surface/conformal_factor.h"
#include "canonform/surface/feature_points.h"
#include "canonform/surface/mesh_repair.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/surface/simplify.h"

#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace canonform::cli {

namespace {

/// The conformal factor of a mesh already validated by validate_and_note().
surface::ConformalFactorResult conformal_of(const std::string& path, const Mesh& m) {
    return on_input(path, [&] {
        surface::ConformalFactorOptions o;
        o.validate = false;
        return surface::conformal_factor(m.V, m.F, o);
    });
}

}  // namespace

void add_conformal(CLI::App& app) {
    struct Args {
        std::string in, out;
        bool json = false, repair = false;
        ParameterArgs normalize;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("conformal", "the conformal factor (eqs. 7-9) as vertex quality of a PLY");
    add_in_out(c, a->in, a->out,
               "output mesh (PLY: conformal factor as vertex quality; .off/.obj/.stl: geometry only)");
    add_parameter(c, surface::normalize_parameter(), a->normalize);
    c->add_flag("--json", a->json, "print a JSON summary on stdout");
    add_repair_flag(c, a->repair);
    c->callback([a] {
        const auto t0 = std::chrono::steady_clock::now();
        const Mesh m = read_large_mesh(a->in, a->repair, a->json);
        const surface::ConformalFactorResult cf = conformal_of(a->in, m);
        io::write_mesh(a->out, m.V, m.F, a->normalize.switches.at("normalize") ? cf.normalized : cf.raw);
        if (a->json)
            print_json({{"vertices", m.V.rows()},
                        {"faces", m.F.rows()},
                        {"min", cf.raw.minCoeff()},
                        {"max", cf.raw.maxCoeff()},
                        {"residual", cf.residual},
                        {"seconds", seconds_since(t0)}});
    });
}

void add_features(CLI::App& app) {
    struct Args {
        std::string in, out;
        ParameterArgs features;  // ring, fill, seed (feature_points.h)
        bool json = false, repair = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand(
        "features", "the feature points (2-ring maxima of the conformal factor) as a point cloud");
    add_in_out(c, a->in, a->out,
               "output point cloud: the feature points (PLY quality: conformal factor; or .off, .obj)", true,
               false);
    add_parameters(c, surface::feature_point_parameters(), a->features);
    c->add_flag("--json", a->json, "print a JSON summary on stdout");
    add_repair_flag(c, a->repair);
    c->callback([a] {
        const auto t0 = std::chrono::steady_clock::now();
        const surface::FeaturePointOptions opt =
            read_parameters(surface::feature_point_parameters(), a->features);
        const Mesh m = read_large_mesh(a->in, a->repair, a->json);
        const surface::ConformalFactorResult cf = conformal_of(a->in, m);
        const surface::FeaturePoints fp = surface::feature_points(m.F, cf.normalized, opt);
        Eigen::MatrixXd P(static_cast<Eigen::Index>(fp.indices.size()), 3);
        Eigen::VectorXd q(P.rows());
        for (size_t k = 0; k < fp.indices.size(); ++k) {
            P.row(static_cast<Eigen::Index>(k)) = m.V.row(fp.indices[k]);
            q(static_cast<Eigen::Index>(k)) = cf.normalized(fp.indices[k]);
        }
        io::write_mesh(a->out, P, Eigen::MatrixXi(0, 3), q);
        if (a->json)
            print_json({{"vertices", m.V.rows()},
                        {"feature_points", fp.indices.size()},
                        {"maxima", fp.num_maxima},
                        {"random", fp.num_random},
                        {"indices", fp.indices},
                        {"seconds", seconds_since(t0)}});
    });
}

void add_canonical(CLI::App& app) {
    // The options are the parameters of every method of the registry (a method's own options,
    // checked by it), plus the choice of method and how to run it.
    struct Args {
        std::string in, out, method = "euclidean", variant;
        int threads = 0;
        bool quiet = false, json = false, repair = false;
        ParameterArgs parameters;  // every parameter of every method, as given
    };
    auto a = std::make_shared<Args>();
    std::vector<std::string> variants;
    for (const canonical::CanonicalMethod* m :
         canonical::canonical_methods_of(canonical::MethodFamily::Euclidean))
        variants.push_back(m->label);
    a->variant = canonical::default_method_of(canonical::MethodFamily::Euclidean).label;
    std::string names = "euclidean (with --variant)";
    for (const canonical::CanonicalMethod* m : canonical::canonical_methods()) names += ", " + m->name;
    auto* c = app.add_subcommand("canonical", "the canonical form of a mesh, by any method of the registry");
    add_in_out(c, a->in, a->out,
               "output mesh (the form; PLY quality: the conformal factor where the method has one)");
    c->add_option("--method", a->method, "the method: " + names);
    c->add_option("--variant", a->variant, "with --method euclidean: the paper's variant")
        ->check(CLI::IsMember(variants));
    // One option per parameter name; its help says which methods take it and their defaults.
    std::map<std::string, std::pair<const Parameter*, std::vector<std::string>>> params;
    std::vector<std::string> order;
    for (const canonical::CanonicalMethod* m : canonical::canonical_methods())
        for (const Parameter& p : m->parameters) {
            auto& entry = params[p.name()];
            if (!entry.first) {
                entry.first = &p;
                order.push_back(p.name());
            }
            entry.second.push_back(m->name + " " + p.default_value());
        }
    for (const std::string& name : order) {
        std::string defaults;
        for (const std::string& d : params[name].second) defaults += (defaults.empty() ? "" : ", ") + d;
        // The value is checked by the method (Parameter::check: finite, in range) once the method
        // is known: methods may give one name different ranges.
        add_parameter(c, *params[name].first, a->parameters, defaults, false);
    }
    c->add_option("--threads", a->threads, "threads of the method's parallel loops (0: every core)")
        ->check(CLI::Range(0, 1024));
    c->add_flag("--quiet", a->quiet, "no progress and no summary line on stderr");
    c->add_flag("--json", a->json, "print a JSON summary on stdout");
    add_repair_flag(c, a->repair);
    c->callback([a] {
        const auto t0 = std::chrono::steady_clock::now();
        canonical::MethodSpec spec;
        spec.name = a->method == "euclidean" ? "euclidean-" + a->variant : a->method;
        const canonical::CanonicalMethod& method = canonical::canonical_method(spec.name);
        for (const auto& [name, value] : a->parameters.given()) {
            if (!method.parameter(name))
                throw UsageError("--" + name + " is not an option of method " + method.name);
            spec.given.emplace_back(name, value);
        }
        canonical::MethodSettings settings;
        try {
            settings = spec.settings();  // checks every value
        } catch (const InputError& e) {
            throw UsageError(e.what());
        }
        canonical::MethodContext context;
        context.threads = a->threads;
        context.progress = terminal_progress(a->quiet || a->json);
        const Mesh m = read_large_mesh(a->in, a->repair, a->json || a->quiet);
        const double read_seconds = seconds_since(t0);
        context.validate = false;
        const canonical::CanonicalForm r =
            on_input(a->in, [&] { return method.run(m.V, m.F, settings, context); });
        if (!r.V.allFinite())
            throw NumericalError("'" + a->in + "': method " + method.name +
                                 " gave a form with NaN or infinite coordinates");
        const auto t_write = std::chrono::steady_clock::now();
        io::write_mesh(a->out, r.V, m.F, r.quality);
        const double write_seconds = seconds_since(t_write);
        if (a->json) {
            nlohmann::ordered_json j = {{"vertices", m.V.rows()}, {"faces", m.F.rows()}};
            for (const auto& [key, value] : r.summary)
                std::visit([&, k = key](const auto& v) { j[k] = v; }, value);
            j["read_seconds"] = read_seconds;
            j["write_seconds"] = write_seconds;
            j["total_seconds"] = seconds_since(t0);
            print_json(j);
        } else if (!a->quiet) {
            std::cerr << "canonical form (" << method.name << "): " << r.description << "\n";
        }
    });
}

void add_simplify(CLI::App& app) {
    struct Args {
        std::string in, out;
        int vertices = 0;
        bool repair = false;
    };
    auto a = std::make_shared<Args>();
    auto* c =
        app.add_subcommand("simplify", "quadric edge collapse to about K vertices, as MeshLab's filter");
    add_in_out(c, a->in, a->out, "output mesh");
    c->add_option("--vertices", a->vertices, "target vertex count K")
        ->required()
        ->check(CLI::Range(4, 100000000));
    add_repair_flag(c, a->repair);
    c->callback([a] {
        const Mesh m = read_input_mesh(a->in, a->repair, false);
        const Mesh s = on_input(a->in, [&] { return surface::simplify_mesh(m, a->vertices); });
        io::write_mesh(a->out, s.V, s.F);
        std::cerr << "simplified " << m.V.rows() << " -> " << s.V.rows() << " vertices\n";
    });
}

namespace {

procedural::FigureProportions class_proportions(const std::string& name) {
    try {
        return procedural::figure_class(name);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

/// A labelled collection: every class (body type) in `poses` poses; pose k < 6 is named pose k
/// (shared by the classes, as the poses of TOSCA's and FAUST's models are), later ones are random
/// and differ between classes. DIR/meshes/CLASS_K.ply, DIR/labels.csv, DIR/corres/CLASS_K.vts
/// (identity: every figure has the same vertex order, so these are exact correspondences).
void generate_collection(const std::string& dir, int n, int poses, int seed,
                         std::vector<std::string> classes) {
    if (classes.empty()) classes = procedural::figure_class_names();
    if (classes.size() < 2) throw UsageError("--classes needs at least two classes");
    for (const auto& c : classes) class_proportions(c);
    io::make_directories(dir + "/meshes");
    io::make_directories(dir + "/corres");
    std::ostringstream labels, ident;
    labels << "path,class\n";
    for (int v = 1; v <= n; ++v) ident << v << "\n";
    for (size_t c = 0; c < classes.size(); ++c) {
        const procedural::FigureProportions prop = class_proportions(classes[c]);
        for (int k = 0; k < poses; ++k) {
            const int pose_id =
                k < procedural::kFigureNamedPoses ? k : 1000 * (seed + 1) + 37 * static_cast<int>(c) + k;
            const procedural::Figure fig = procedural::make_figure(n, procedural::figure_pose(pose_id), prop);
            const std::string name = classes[c] + "_" + std::to_string(k);
            io::write_ply(dir + "/meshes/" + name + ".ply", fig.mesh.V.cast<float>().cast<double>(),
                          fig.mesh.F);
            io::write_file_atomic(dir + "/corres/" + name + ".vts", ident.str());
            labels << "meshes/" << name << ".ply," << classes[c] << "\n";
        }
    }
    io::write_file_atomic(dir + "/labels.csv", labels.str());
    std::cerr << "generate: " << classes.size() * static_cast<size_t>(poses) << " figures (" << classes.size()
              << " classes x " << poses << " poses, " << n << " vertices) in " << dir << "\n";
}

}  // namespace

void add_generate(CLI::App& app) {
    struct Args {
        std::string out, cls = "standard", collection, classes;
        int vertices = 5000, pose = 0, poses = 10, seed = 0;
    };
    auto a = std::make_shared<Args>();
    auto* c =
        app.add_subcommand("generate", "a procedural articulated figure, or a labelled collection of them");
    c->add_option("OUT", a->out, "output mesh (one figure)")->check(mesh_output());
    c->add_option("--vertices", a->vertices, "vertices per figure")->check(CLI::Range(500, 2000000));
    c->add_option("--pose", a->pose, "pose: 0-5 named poses, others seeded random ones")
        ->check(CLI::Range(0, 1000000000));
    c->add_option("--class", a->cls,
                  "body type of the figure (standard, long-arms, short-legs, long-tail, stocky, "
                  "long-neck)");
    c->add_option("--collection", a->collection, "write a labelled collection into this folder instead");
    c->add_option("--poses", a->poses, "collection: poses per class")->check(CLI::Range(2, 1000));
    c->add_option("--classes", a->classes, "collection: comma-separated body types (empty: all six)");
    c->add_option("--seed", a->seed, "collection: seed of the random poses")->check(CLI::Range(0, 100000));
    c->callback([a] {
        if (!a->collection.empty()) {
            if (!a->out.empty()) throw UsageError("generate takes OUT or --collection DIR, not both");
            return generate_collection(a->collection, a->vertices, a->poses, a->seed, split_list(a->classes));
        }
        if (a->out.empty()) throw UsageError("generate needs OUT (or --collection DIR)");
        const procedural::Figure fig =
            procedural::make_figure(a->vertices, procedural::figure_pose(a->pose), class_proportions(a->cls));
        // Rounded to float, the precision MeshLab 2020.09 works in, so that the tool and MeshLab
        // compute on exactly the same coordinates.
        io::write_mesh(a->out, fig.mesh.V.cast<float>().cast<double>(), fig.mesh.F);
    });
}

void add_check(CLI::App& app) {
    struct Args {
        std::string in, repair_out;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand(
        "check",
        "read and validate a mesh file with the tool's own readers, naming every problem (also those "
        "MeshLab's importers crash or abort on); with --repair OUT, write a repaired copy MeshLab can open. "
        "Exit status 0: no problem; 1: problems (or an unreadable file)");
    c->add_option("MESH", a->in, "the mesh file (OFF, PLY, OBJ or STL)")->required();
    c->add_option(
         "--repair", a->repair_out,
         "OUT: drop faces that name vertices the file does not have, then merge duplicate vertices, remove "
         "zero-area and duplicate faces, keep the largest connected piece, drop unreferenced vertices "
         "(the --repair of the other commands), and write the result to OUT")
        ->check(mesh_output());
    c->add_flag("--json", a->json, "print the findings as JSON on stdout");
    c->callback([a] {
        nlohmann::ordered_json j = {{"file", a->in}};
        std::vector<std::string> problems, notes;
        auto say = [&](const std::string& line) {
            if (!a->json) std::cout << line << "\n";
        };
        // The file itself: our readers refuse what would crash or exhaust MeshLab's importers.
        io::ReadOptions ro;
        ro.drop_bad_faces = true;  // to name them all and to repair; still a problem below
        io::MeshFile file;
        try {
            file = io::read_mesh_file(a->in, ro);
        } catch (const InputError& e) {
            const std::string what = e.what();
            problems.push_back(what);
            if (what.find("header lies") != std::string::npos ||
                what.find("more than this program handles") != std::string::npos)
                notes.push_back(
                    "MeshLab's PLY and OFF importers allocate what a header claims before reading any data: "
                    "MeshLab aborts (out of memory) on such a file before any filter runs");
            j["readable"] = false;
            j["problems"] = problems;
            j["notes"] = notes;
            if (a->json) {
                print_json(j);
            } else {
                say(a->in + ": unreadable");
                for (const auto& p : problems) say("  problem: " + p);
                for (const auto& n : notes) say("  note: " + n);
                say("  not repairable here: the file's structure itself is broken (truncated or corrupt?)");
            }
            throw ExitStatus{1};
        }
        const Mesh& m = file.mesh;
        j["readable"] = true;
        j["vertices"] = m.V.rows();
        j["faces"] = m.F.rows();
        if (file.dropped_faces > 0) {
            problems.push_back(std::to_string(file.dropped_faces) +
                               (file.dropped_faces == 1 ? " face names a vertex" : " faces name vertices") +
                               " the file does not have (first: " + file.first_dropped + ")");
            notes.push_back(
                "MeshLab's OFF importer uses such an index as a pointer: MeshLab crashes on this file "
                "before any filter runs; `canonform check FILE --repair OUT` drops those faces");
        }
        surface::MeshReport report;
        for (const surface::MeshProblem& p : surface::mesh_problems(m.V, m.F, {}, &report))
            problems.push_back(p.message);
        // What --repair would change (merges and removals the filters' own 'Repair' also make).
        const surface::MeshRepair fix =
            m.F.rows() > 0 ? surface::repair_mesh(m.V, m.F) : surface::MeshRepair{};
        if (fix.changed()) notes.push_back("--repair would " + fix.summary());
        if (report.boundary_edges > 0)
            notes.push_back("open surface: " + std::to_string(report.boundary_edges) +
                            " boundary edges (allowed)");
        j["edges"] = report.edges;
        j["components"] = report.components;
        j["boundary_edges"] = report.boundary_edges;
        j["problems"] = problems;
        j["notes"] = notes;

        if (!a->repair_out.empty()) {
            const Mesh& r = fix.changed() ? fix.mesh : m;
            const std::vector<surface::MeshProblem> left = surface::mesh_problems(r.V, r.F);
            io::write_mesh(a->repair_out, r.V, r.F);
            nlohmann::ordered_json rj = {{"output", a->repair_out},
                                         {"vertices", r.V.rows()},
                                         {"faces", r.F.rows()},
                                         {"dropped_faces", file.dropped_faces},
                                         {"summary", fix.summary()}};
            std::vector<std::string> left_messages;
            for (const surface::MeshProblem& p : left) left_messages.push_back(p.message);
            rj["problems_left"] = left_messages;
            j["repair"] = rj;
            if (!a->json) {
                say(a->in + " -> " + a->repair_out + ": " +
                    (file.dropped_faces > 0 ? "dropped " + std::to_string(file.dropped_faces) +
                                                  " faces with indices out of range; "
                                            : std::string()) +
                    fix.summary());
                for (const auto& p : left_messages)
                    say("  still a problem (not repairable without inventing geometry): " + p);
            }
            if (a->json) print_json(j);
            if (!left.empty()) throw ExitStatus{1};
            return;
        }
        if (a->json) {
            print_json(j);
        } else {
            say(a->in + ": " + std::to_string(m.V.rows()) + " vertices, " + std::to_string(m.F.rows()) +
                " faces, " + std::to_string(report.components) + " connected piece" +
                (report.components == 1 ? "" : "s"));
            for (const auto& p : problems) say("  problem: " + p);
            for (const auto& n : notes) say("  note: " + n);
            say(problems.empty()
                    ? "  ok: the filters and the tool accept this mesh"
                    : "  the filters and the tool refuse this mesh (" + std::to_string(problems.size()) +
                          " problem" + (problems.size() == 1 ? "" : "s") + ")" +
                          (fix.changed() || file.dropped_faces > 0
                               ? "; `canonform check " + a->in + " --repair OUT.ply` writes a repaired copy"
                               : ""));
        }
        if (!problems.empty()) throw ExitStatus{1};
    });
}

}  // namespace canonform::cli
