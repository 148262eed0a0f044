// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the view commands of canonform-full - views (Qt pictures) and codebook (FAISS's
// k-means); descriptor and distance, which the lean program carries too, are in
// descriptor_commands.cpp.
#include "cli.h"
#include "picture.h"  // write_view_images
#include "view_args.h"

#include "canonform/io/files.h"
#include "canonform/views/view_descriptor.h"

#include <cstdint>
#include <iostream>
#include <memory>
#include <numeric>

namespace canonform::cli {

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
        std::vector<std::size_t> counts;
        std::int64_t rows = 0;
        ProgressLine progress(false);
        for (size_t k = 0; k < a->meshes.size(); ++k) {
            features.push_back(a->views_of(a->meshes[k]).features);
            counts.push_back(views::feature_rows(features.back()));
            rows += static_cast<std::int64_t>(counts.back());
            progress.update(std::to_string(k + 1) + "/" + std::to_string(a->meshes.size()) + " meshes, " +
                                std::to_string(rows) + " SIFT descriptors",
                            k + 1 == a->meshes.size());
        }
        views::CodebookOptions co;
        co.words = a->words;
        co.seed = a->options().pose.seed;  // --seed: the rectilinearity restarts' and the codebook's
        co.method = views::parse_codebook_method(a->random ? "random" : a->method);
        co.sample = a->sample;
        const views::Codebook cb = views::Codebook::train_on_rows(
            views::stacked_rows(
                counts, views::Codebook::training_rows(rows, co),
                [&](std::size_t g) -> const std::vector<views::SiftDescriptors>& { return features[g]; }),
            rows, co);
        cb.save(a->out);
        std::cerr << "codebook of " << cb.size() << " words from " << rows << " descriptors -> " << a->out
                  << "\n";
    });
}

}  // namespace canonform::cli
