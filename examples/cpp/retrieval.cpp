// SPDX-License-Identifier: GPL-3.0-or-later
// View-based retrieval on a few generated figures: 66 depth views and SIFT per mesh, a codebook,
// bag-of-features histograms, clock-matching distances and the psbTable measures.
//   example_retrieval
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/retrieval/retrieval_measures.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"

#include <cstdio>
#include <string>
#include <vector>

int main() {
    namespace views = canonform::views;
    // two classes (body types) in three poses each, 2000 vertices
    std::vector<canonform::Mesh> meshes;
    std::vector<std::string> labels;
    for (const std::string& cls : {std::string("standard"), std::string("long-arms")})
        for (int pose = 0; pose < 3; ++pose) {
            meshes.push_back(canonform::procedural::make_figure(2000,
                                                                canonform::procedural::figure_pose(pose),
                                                                canonform::procedural::figure_class(cls))
                                 .mesh);
            labels.push_back(cls);
        }

    // canonical form, then the 66 views and their SIFT features
    std::vector<views::ViewSet> sets;
    std::vector<const std::vector<views::SiftDescriptors>*> all;
    for (const auto& m : meshes) {
        const auto form = canonform::canonical::euclidean_canonical_form(m.V, m.F);
        sets.push_back(views::compute_views(form.V, m.F));
    }
    for (const auto& s : sets) all.push_back(&s.features);

    // a small codebook trained on every descriptor, and one histogram per view
    views::CodebookOptions co;
    co.words = 100;
    const views::Codebook codebook = views::Codebook::train(views::stack_features(all), co);
    std::vector<std::vector<views::Histogram>> histograms;
    for (const auto& s : sets) histograms.push_back(views::view_histograms(s, codebook));

    // clock matching over the 24 cube rotations, then the measures
    const Eigen::MatrixXf D = views::distance_matrix(histograms, views::rotation_view_maps());
    const auto e = canonform::retrieval::evaluate(D.cast<double>(), labels);
    std::printf("NN %.3f, first tier %.3f, second tier %.3f, E %.3f, DCG %.3f\n", e.micro.nn,
                e.micro.first_tier, e.micro.second_tier, e.micro.e_measure, e.micro.dcg);
    return 0;
}
