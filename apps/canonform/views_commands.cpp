// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the view-descriptor commands - views, codebook, descriptor, distance.
#include "cli.h"
#include "picture.h"  // write_view_images

#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#include "canonform/views/view_parameters.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <numeric>

namespace canonform::cli {

namespace {

/// Options the view commands share.
struct ViewArgs {
    ParameterArgs view;  // --sift, --image-size (--size), --seed: views/view_parameters.h
    bool repair = false;

    void add(CLI::App* c) {
        add_parameters(c, views::view_descriptor_parameters(), view);
        add_repair_flag(c, repair);
    }
    views::ViewDescriptorOptions options() const {
        return read_parameters(views::view_descriptor_parameters(), view);
    }
    views::ViewSet views_of(const std::string& path, bool images = false) const {
        const Mesh m = read_input_mesh(path, repair, true, false);  // compute_views() validates
        views::ViewDescriptorOptions o = options();
        o.keep_images = images;
        return on_input(path, [&] { return views::compute_views(m.V, m.F, o); });
    }
};

}  // namespace

void add_views(CLI::App& app) {
    struct Args : ViewArgs {
        std::string in, dir;
    };
    auto a = std::make_shared<Args>();
    auto* c = app.add_subcommand("views", "the 66 depth views of a mesh as PNG, and a contact sheet of them");
    add_in_out(c, a->in, a->dir, "output folder", false);
    a->add(c);
    c->callback([a] {
        const views::ViewSet vs = a->views_of(a->in, true);
        io::make_directories(a->dir);
        write_view_images(a->dir, vs);
        const auto counts = vs.keypoint_counts();
        const int total = std::accumulate(counts.begin(), counts.end(), 0);
        std::cerr << "66 views of " << a->options().image_size << " px in " << a->dir << " (pose by "
                  << (vs.pose.used_rectilinearity ? "rectilinearity" : "PCA") << ", " << total
                  << " SIFT keypoints)\n";
    });
}

void add_codebook(CLI::App& app) {
    struct Args : ViewArgs {
        std::string out;
        std::vector<std::string> meshes;
        int words = 1500;
        bool random = false;
        std::string method = views::codebook_method_name(views::CodebookOptions::kDefaultMethod);
        std::int64_t sample = views::kDefaultCodebookSample;
    };
    auto a = std::make_shared<Args>();
    auto* c =
        app.add_subcommand("codebook", "a codebook of visual words trained on the SIFT features of meshes");
    c->add_option("OUT", a->out, "output codebook file")->required();
    c->add_option("MESH", a->meshes, "meshes to train on")->required();
    c->add_option("--words", a->words, "visual words")->check(CLI::Range(1, 1000000));
    c->add_option("--training", a->method,
                  "kmeans (FAISS), lloyd (k-means++ and Lloyd) or random (random "
                  "training descriptors as words)")
        ->check(CLI::IsMember({"kmeans", "lloyd", "random"}));
    c->add_flag("--random", a->random, "the same as --training random");
    c->add_option("--sample", a->sample, "train on this many descriptors drawn from all (0: all)")
        ->check(CLI::Range(std::int64_t(0), std::int64_t(2000000000)));
    a->add(c);
    c->callback([a] {
        std::vector<std::vector<views::SiftDescriptors>> features;
        Eigen::Index rows = 0;
        ProgressLine progress(false);
        for (size_t k = 0; k < a->meshes.size(); ++k) {
            features.push_back(a->views_of(a->meshes[k]).features);
            for (const auto& f : features.back()) rows += f.rows();
            progress.update(std::to_string(k + 1) + "/" + std::to_string(a->meshes.size()) + " meshes, " +
                                std::to_string(rows) + " SIFT descriptors",
                            k + 1 == a->meshes.size());
        }
        std::vector<const std::vector<views::SiftDescriptors>*> sets;
        for (const auto& f : features) sets.push_back(&f);
        views::CodebookOptions co;
        co.words = a->words;
        co.seed = a->options().pose.seed;  // --seed: the rectilinearity restarts' and the codebook's
        co.method = views::parse_codebook_method(a->random ? "random" : a->method);
        co.sample = a->sample;
        const views::Codebook cb = views::Codebook::train(views::stack_features(sets), co);
        cb.save(a->out);
        std::cerr << "codebook of " << cb.size() << " words from " << rows << " descriptors -> " << a->out
                  << "\n";
    });
}

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
