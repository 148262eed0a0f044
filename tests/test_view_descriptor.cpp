// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_directions.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace canonform;
using namespace canonform::views;
using namespace canonform::procedural;

namespace {

SiftDescriptors stack(const std::vector<const ViewSet*>& sets) {
    Eigen::Index rows = 0;
    for (const auto* s : sets)
        for (const auto& f : s->features) rows += f.rows();
    SiftDescriptors all(rows, 128);
    Eigen::Index r = 0;
    for (const auto* s : sets)
        for (const auto& f : s->features) {
            all.middleRows(r, f.rows()) = f;
            r += f.rows();
        }
    return all;
}

}  // namespace

TEST(ViewDescriptor, SameShapeInAnotherFrameIsNearAndAnotherShapeIsFar) {
    const Figure fig = make_figure(3000, figure_pose(2));
    const Eigen::MatrixXd moved =
        ((2.7 * fig.mesh.V * test::random_rotation(31).transpose()).rowwise() + Eigen::RowVector3d(3, -1, 8));
    const Mesh torus = make_torus(60, 24, 1.0, 0.35);

    const ViewSet a = compute_views(fig.mesh.V, fig.mesh.F);
    const ViewSet b = compute_views(moved, fig.mesh.F);
    const ViewSet c = compute_views(torus.V, torus.F);
    ASSERT_EQ(a.images.size(), 66u);
    CodebookOptions co;
    co.words = 200;
    const Codebook cb = Codebook::train(stack({&a, &b, &c}), co);
    const auto maps = rotation_view_maps();
    const double same = clock_matching_distance(view_histograms(a, cb), view_histograms(b, cb), maps);
    const double other = clock_matching_distance(view_histograms(a, cb), view_histograms(c, cb), maps);
    std::printf("      clock matching: figure vs moved copy %.2f, figure vs torus %.2f (66 views)\n", same,
                other);
    EXPECT_LT(same, 0.25 * other);
    EXPECT_LT(same, 10.0);  // of at most 66
}

TEST(ViewDescriptor, RejectsBadMeshesAndAcceptsSeveralComponents) {
    const Mesh s = make_icosphere(2);
    EXPECT_THROW(compute_views(s.V, Eigen::MatrixXi(0, 3)), InputError);  // a point cloud
    Eigen::MatrixXi F = s.F;
    F(0, 1) = F(0, 0);  // degenerate face
    EXPECT_THROW(compute_views(s.V, F), InputError);
    // Two spheres side by side: a valid scene with two components.
    Eigen::MatrixXd V2(2 * s.V.rows(), 3);
    V2 << s.V, (s.V.rowwise() + Eigen::RowVector3d(3, 0, 0));
    Eigen::MatrixXi F2(2 * s.F.rows(), 3);
    F2 << s.F, (s.F.array() + static_cast<int>(s.V.rows())).matrix();
    EXPECT_NO_THROW(compute_views(V2, F2));
}

TEST(ViewDescriptor, StackedRowsAreTheStacksRowsWithoutTheStack) {
    // Three models with views of 0-6 features; the second model is never asked for.
    std::vector<std::vector<SiftDescriptors>> models(3);
    float next = 0;
    for (int g = 0; g < 3; ++g)
        for (int v = 0; v < 4; ++v) {
            const int n = (g * 5 + v * 3) % 7;
            SiftDescriptors d(n, 128);
            for (Eigen::Index i = 0; i < d.size(); ++i) d.data()[i] = next++;
            models[static_cast<size_t>(g)].push_back(d);
        }
    std::vector<const std::vector<SiftDescriptors>*> sets;
    std::vector<std::size_t> counts;
    for (const auto& m : models) {
        sets.push_back(&m);
        std::size_t n = 0;
        for (const auto& v : m) n += static_cast<std::size_t>(v.rows());
        counts.push_back(n);
    }
    const SiftDescriptors all = stack_features(sets);
    const int first_of_third = static_cast<int>(counts[0] + counts[1]);
    const std::vector<int> rows = {first_of_third + 2, 0, static_cast<int>(all.rows()) - 1, 3,
                                   first_of_third};
    std::vector<std::size_t> asked;
    const auto get = [&](std::size_t g) -> const std::vector<SiftDescriptors>& {
        asked.push_back(g);
        return models[g];
    };
    const SiftDescriptors got = stacked_rows(counts, rows, get);
    ASSERT_EQ(got.rows(), static_cast<Eigen::Index>(rows.size()));
    for (size_t i = 0; i < rows.size(); ++i)
        EXPECT_EQ(got.row(static_cast<Eigen::Index>(i)), all.row(rows[i]));
    EXPECT_EQ(asked, (std::vector<std::size_t>{0, 2}));
    // A model whose features changed, and a row past the stack, are refused.
    std::vector<std::size_t> wrong = counts;
    wrong[0] += 1;
    EXPECT_THROW(stacked_rows(wrong, rows, get), InputError);
    EXPECT_THROW(stacked_rows(counts, {static_cast<int>(all.rows())}, get), InputError);
}
