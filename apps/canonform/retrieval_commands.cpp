// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the retrieval commands - retrieve, evaluate, grid, pr.
#include "cli.h"
#include "grid.h"
#include "pr_plot.h"

#include "canonform/io/csv.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/retrieval/retrieval_measures.h"
#include "canonform/views/view_parameters.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace canonform::cli {

namespace {

/// The name of a run folder, for a title: its last path component ("tosca_o" of "runs/tosca_o/").
std::string run_name(const std::string& run) {
    std::filesystem::path p = std::filesystem::path(run).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    return p.filename().string();
}

/// RUN/pr.png: every method's precision-recall curve on one plot (the paper's Figs. 10 and 11).
/// Returns the report's line about it.
std::string pr_plot(const std::string& run) {
    try {
        write_pr_plot(run + "/pr.png", read_pr_curves(run), run_name(run));
        return "\n![precision-recall](pr.png)\n";
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "retrieve: no precision-recall plot: %s\n", ex.what());
        return std::string("\n(No precision-recall plot: ") + ex.what() + ")\n";
    }
}

/// RUN/grid.png: originals beside their canonical forms, one model per class (the paper's
/// Fig. 8). Returns the report's line about it ("" if the run has only `none`).
std::string grid_picture(const std::string& run, const std::vector<canonical::MethodSpec>& methods) {
    GridOptions g;
    g.run = run;
    for (const canonical::MethodSpec& m : methods)
        if (m.name != "none") g.methods.push_back(m.folder());
    if (g.methods.empty()) return "";
    g.panel = g.methods.size() > 4 ? 110 : 150;
    try {
        write_grid(run + "/grid.png", g);
        return "\n![originals (first row) and their canonical forms, one model per class; colour = height "
               "along the original's longest axis](grid.png)\n";
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "retrieve: no grid picture: %s\n", ex.what());
        return std::string("\n(No grid picture: ") + ex.what() + ")\n";
    }
}

void print_row(std::ostream& o, const std::string& name, const retrieval::Measures& m) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %d |\n", name.c_str(), m.nn,
                  m.first_tier, m.second_tier, m.e_measure, m.dcg, m.queries);
    o << buf;
}

}  // namespace

void add_experiment_options(CLI::App* c, ExperimentArgs& a) {
    std::string names;
    for (const canonical::CanonicalMethod* m : canonical::canonical_methods())
        names += (names.empty() ? "" : ", ") + m->name;
    c->add_option("--dataset", a.o.dataset, "collection folder (label paths are relative to it)")->required();
    c->add_option("--labels", a.o.labels, "labels file, rows path,class (default: DATASET/labels.csv)");
    c->add_option("--out", a.o.out, "run folder (for a sharded run on a filesystem every machine shares)")
        ->required();
    c->add_option("--method", a.methods,
                  "comma-separated methods, each NAME[:KEY=VALUE...] (" + names +
                      "; e.g. euclidean-N:beta=65), or fused:A+B[+C...] with optional weights "
                      "fused:A*0.5+B*0.5: the weighted sum of the members' distances z-normalised per "
                      "query, symmetrised (fused-median:A+B: the previous rule, each matrix divided "
                      "by its median off-diagonal distance; members are added if not listed)");
    c->add_option("--words", a.o.words, "codebook size")->check(CLI::Range(1, 1000000));
    const bool faiss = views::CodebookOptions::kDefaultMethod == views::CodebookOptions::Method::KMeans;
    c->add_option("--codebook", a.o.codebook,
                  std::string("how the codebook is made per method: kmeans (FAISS k-means, ") +
                      (faiss ? "default" : "not in this build") + "), lloyd (our k-means++ and Lloyd" +
                      (faiss ? "" : ", default") +
                      "), random (random training "
                      "descriptors as words), or a codebook FILE used for every method");
    c->add_option("--codebook-sample", a.o.codebook_training.sample,
                  "train the codebook on this many descriptors drawn from the method's features (0: all)")
        ->check(CLI::Range(0L, 2000000000L));
    c->add_option("--simplify", a.o.simplify, "simplify every mesh to this many vertices first (0: no)")
        ->check(CLI::Range(0, 100000000));
    c->add_option("--noise", a.o.noise, "vertex noise, as a fraction of the mean edge length")
        ->check(finite_range(0, 10));
    c->add_option("--seed", a.o.seed, "seed of the noise and the codebook")
        ->check(finite_range(0, 4294967295.0));
    add_parameter(c, *find_parameter(views::view_descriptor_parameters().parameters(), "sift"), a.sift);
    add_repair_flag(c, a.o.repair);
}

retrieval::ExperimentOptions finish_experiment_options(const ExperimentArgs& a, bool fused) {
    retrieval::ExperimentOptions o = a.o;
    o.views.sift.backend = read_parameters(views::view_descriptor_parameters(), a.sift).sift.backend;
    if (o.labels.empty()) o.labels = o.dataset + "/labels.csv";
    if (o.codebook == "kmeans" || o.codebook == "lloyd" || o.codebook == "random") {
        o.codebook_training.method = views::parse_codebook_method(o.codebook);
        o.codebook.clear();
    }
    for (const std::string& m : split_list(a.methods)) {
        if (!retrieval::is_fused_spec(m))
            o.methods.push_back(canonical::parse_method_spec(m));
        else if (fused)
            o.fused.push_back(retrieval::parse_fused_spec(m));
        else
            throw UsageError(
                "--method " + m +
                ": fused methods are computed by `retrieve` from the members' "
                "distance matrices, not by a sharded run (run retrieve on the merged run folder)");
    }
    return o;
}

void add_retrieve(CLI::App& app) {
    struct Args : ExperimentArgs {
        int threads = 0;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("retrieve",
                                 "a retrieval experiment over a labelled collection: forms, views, "
                                 "codebook, distances and measures per method");
    add_experiment_options(c, *a);
    c->add_option("--threads", a->threads, "meshes in parallel (0: every core)")->check(CLI::Range(0, 1024));
    c->callback([a] {
        retrieval::ExperimentOptions o = finish_experiment_options(*a, true);
        o.threads = a->threads;
        o.log = [](const std::string& line) { std::cerr << line << "\n"; };
        o.progress = [](const std::string& method) { return terminal_progress(false, method); };
        const retrieval::Experiment experiment(o);
        const std::vector<retrieval::MethodOutcome> outcomes = experiment.run();
        const std::string report = retrieval::report_markdown(
            o, experiment.models().size(), outcomes, pr_plot(o.out) + grid_picture(o.out, o.methods));
        io::write_file_atomic(o.out + "/report.md", report);
        std::cout << report;
    });
}

void add_evaluate(CLI::App& app) {
    struct Args {
        std::string matrix, labels, pr;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("evaluate",
                                 "NN, first and second tier, E-measure and DCG of a distance matrix "
                                 "(psbTable's definitions)");
    c->add_option("MATRIX", a->matrix, "distance matrix: float32 row-major, or .csv")->required();
    c->add_option("--labels", a->labels, "labels file, rows path,class in matrix order")->required();
    c->add_flag("--json", a->json, "print the measures as JSON");
    c->add_option("--pr", a->pr, "write the 20-point precision-recall curve to this CSV");
    c->callback([a] {
        const Eigen::MatrixXd D = io::read_distance_matrix(a->matrix);
        std::vector<std::string> labels;
        for (const auto& row : io::read_labels(a->labels)) labels.push_back(row.label);
        const retrieval::Evaluation e = retrieval::evaluate(D, labels);
        if (!a->pr.empty()) {
            std::ostringstream pr;
            pr << "recall,precision\n";
            for (size_t k = 0; k < e.recall.size(); ++k) pr << e.recall[k] << "," << e.precision[k] << "\n";
            io::write_file_atomic(a->pr, pr.str());
        }
        if (a->json) {
            nlohmann::ordered_json classes = nlohmann::ordered_json::object();
            for (size_t k = 0; k < e.classes.size(); ++k)
                classes[e.classes[k]] = retrieval::to_json(e.per_class[k]);
            print_json({{"micro", retrieval::to_json(e.micro)},
                        {"macro", retrieval::to_json(e.macro)},
                        {"classes", classes},
                        {"precision", e.precision}});
            return;
        }
        std::cout << "| average | NN | 1-Tier | 2-Tier | E-measure | DCG | queries "
                     "|\n|---|---|---|---|---|---|---|\n";
        print_row(std::cout, "micro", e.micro);
        print_row(std::cout, "macro", e.macro);
        std::cout << "\n| class | NN | 1-Tier | 2-Tier | E-measure | DCG | queries "
                     "|\n|---|---|---|---|---|---|---|\n";
        for (size_t k = 0; k < e.classes.size(); ++k) print_row(std::cout, e.classes[k], e.per_class[k]);
        if (!e.skipped_classes.empty()) {
            std::cout << "\nleft out (two models or fewer):";
            for (const auto& cls : e.skipped_classes) std::cout << " " << cls;
            std::cout << "\n";
        }
    });
}

void add_grid(CLI::App& app) {
    struct Args {
        std::string out, methods;
        GridOptions g;
    };
    auto a = std::make_shared<Args>();
    auto* c =
        app.add_subcommand("grid", "originals beside their canonical forms from a retrieve run (Figs. 8, 9)");
    c->add_option("OUT", a->out, "output PNG")->required();
    c->add_option("RUN", a->g.run, "a `canonform retrieve` run folder")->required();
    c->add_option("--methods", a->methods,
                  "comma-separated method folders, each DIR[=LABEL] (default: all but none)");
    c->add_option("--class", a->g.cls, "the models of this class (Fig. 9) instead of one per class (Fig. 8)");
    c->add_option("--columns", a->g.columns, "at most this many columns")->check(CLI::Range(1, 10000));
    c->add_option("--size", a->g.panel, "pixels per panel")->check(CLI::Range(16, 2048));
    c->callback([a] {
        a->g.methods = split_list(a->methods);
        const int n = write_grid(a->out, a->g);
        std::cerr << "grid: " << n << " models, "
                  << (a->g.methods.empty() ? std::string("every method") : a->methods) << " -> " << a->out
                  << "\n";
    });
}

void add_pr(CLI::App& app) {
    struct Args {
        std::string out, title;
        std::vector<std::string> runs;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("pr",
                                 "precision-recall curves of every method of one or more retrieve runs on "
                                 "one plot (Figs. 10, 11)");
    c->add_option("OUT", a->out, "output PNG")->required();
    c->add_option("RUN", a->runs,
                  "`canonform retrieve` run folders, each RUN[=LABEL]: LABEL goes before the "
                  "method names of that run (e.g. tosca_o=O tosca_s2k=S)")
        ->required();
    c->add_option("--title", a->title, "the title (default: the run folder's name)");
    c->callback([a] {
        std::vector<PrCurve> curves;
        for (const std::string& r : a->runs) {
            const size_t eq = r.find('=');
            const std::string run = r.substr(0, eq), label = eq == std::string::npos ? "" : r.substr(eq + 1);
            std::vector<PrCurve> some = read_pr_curves(run, label);
            if (some.empty())
                throw InputError("'" + run +
                                 "' has no METHOD/pr.csv: is it a `canonform retrieve` run folder?");
            curves.insert(curves.end(), some.begin(), some.end());
        }
        const std::string first = a->runs[0].substr(0, a->runs[0].find('='));
        write_pr_plot(a->out, curves, a->title.empty() ? run_name(first) : a->title);
        std::cerr << "pr: " << curves.size() << " curves -> " << a->out << "\n";
    });
}

}  // namespace canonform::cli
