// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the view descriptor of a mesh and the distances between descriptors - descriptor
// and distance. Both programs carry them (main.cpp): they need only the views area, which is Eigen
// alone (its own SIFT, renders, codebook reading and word assignment, descriptor files, clock
// matching). In the lean program, `descriptor --sift opencv` runs canonform-full, which links OpenCV.
#include "cli.h"
#include "view_args.h"

#include "canonform/io/distance_matrix_file.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/sift_features.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"

#include <iostream>
#include <memory>
#include <numeric>

namespace canonform::cli {

void add_descriptor(CLI::App& app) {
    struct Args : ViewArgs {
        std::string in, out, codebook;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("descriptor",
                                 "the view descriptor file of a mesh (histograms, or raw SIFT features)");
    add_in_out(c, a->in, a->out, "output descriptor file (.cfvd)", false);
    c->add_option("--codebook", a->codebook, "codebook file (without: raw SIFT features)");
    c->add_flag("--json", a->json, "print a JSON summary on stdout");
    a->add(c);
    c->callback([a] {
#ifdef CANONFORM_TOOL_LEAN
        // An extractor this program does not link (`--sift opencv`: OpenCV) is canonform-full's.
        const views::SiftBackend sift = a->options().sift.backend;
        if (!views::sift_backend_available(sift)) throw RunFull{"--sift " + views::sift_backend_name(sift)};
#endif
        const auto t0 = std::chrono::steady_clock::now();
        views::Codebook cb;
        if (!a->codebook.empty()) cb = views::Codebook::load(a->codebook);
        const views::ViewSet vs = a->views_of(a->in);
        const views::ModelDescriptor d = views::make_descriptor(
            vs.features, a->codebook.empty() ? nullptr : &cb, a->in, a->options().image_size);
        views::write_descriptor(a->out, d);
        const int total = std::accumulate(d.keypoints_per_view.begin(), d.keypoints_per_view.end(), 0);
        if (a->json)
            print_json({{"views", d.views},
                        {"keypoints", total},
                        {"codebook_words", d.codebook_words},
                        {"seconds", seconds_since(t0)}});
    });
}

void add_distance(CLI::App& app) {
    struct Args {
        std::string out;
        std::vector<std::string> descriptors;
        int threads = 0;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("distance", "the clock-matching distance matrix of descriptor files");
    c->add_option("OUT", a->out, "output matrix: float32 row-major (and OUT.csv as text)")->required();
    c->add_option("DESC", a->descriptors, "descriptor files made with a codebook (two or more)")
        ->required()
        ->expected(2, -1);
    c->add_option("--threads", a->threads, "threads (0: every core)")->check(CLI::Range(0, 1024));
    c->callback([a] {
        std::vector<std::vector<views::Histogram>> models;
        int words = -1;
        for (const auto& path : a->descriptors) {
            views::ModelDescriptor d = views::read_descriptor(path);
            if (d.codebook_words == 0)
                throw InputError("'" + path + "' holds raw SIFT features: make descriptors with --codebook");
            if (words >= 0 && d.codebook_words != words)
                throw InputError("'" + path + "' uses a codebook of " + std::to_string(d.codebook_words) +
                                 " words, the others " + std::to_string(words));
            words = d.codebook_words;
            models.push_back(std::move(d.histograms));
        }
        const auto t0 = std::chrono::steady_clock::now();
        const Eigen::MatrixXf D = views::distance_matrix(models, views::rotation_view_maps(), a->threads);
        const double secs = seconds_since(t0);
        io::write_distance_matrix(D, a->out, a->out + ".csv");
        std::cerr << D.rows() << " x " << D.cols() << " clock-matching distances in " << secs << " s -> "
                  << a->out << " (float32 row-major) and " << a->out << ".csv\n";
    });
}

}  // namespace canonform::cli
