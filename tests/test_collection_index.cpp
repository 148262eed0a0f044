// SPDX-License-Identifier: GPL-3.0-or-later
// The indexed collection: queries give the distance matrix's rows (the same order, the member
// itself first), through the file format, and refuse what 16 bits cannot hold.
#include "canonform/common/errors.h"
#include "canonform/io/distance_matrix_file.h"
#include "canonform/io/files.h"
#include "canonform/io/mesh_io.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/retrieval/collection_index.h"
#include "canonform/retrieval/experiment.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_descriptor.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <numeric>

using namespace canonform;
using namespace canonform::retrieval;
using namespace canonform::canonical;
using namespace canonform::procedural;
namespace fs = std::filesystem;

namespace {

/// A finished `retrieve` run of seven figures (method none), made once per process.
const std::string& run_folder() {
    static const std::string run = [] {
        const std::string d = (fs::temp_directory_path() / ("canonform_test_index_" + std::to_string(getpid()))).string();
        fs::remove_all(d);
        io::make_directories(d + "/data/meshes");
        std::string labels = "path,class\n";
        for (const std::string cls : {"standard", "long-arms"})
            for (int pose = 0; pose < (cls == "standard" ? 4 : 3); ++pose) {
                const Figure f = make_figure(600, figure_pose(pose), figure_class(cls));
                const std::string name = cls + "_" + std::to_string(pose) + ".ply";
                io::write_ply(d + "/data/meshes/" + name, f.mesh.V, f.mesh.F);
                labels += "meshes/" + name + "," + cls + "\n";
            }
        io::write_file_atomic(d + "/data/labels.csv", labels);
        ExperimentOptions o;
        o.dataset = d + "/data";
        o.labels = o.dataset + "/labels.csv";
        o.out = d + "/run";
        o.methods = {parse_method_spec("none")};
        o.words = 40;
        o.threads = 2;
        Experiment(o).run();
        return d;
    }();
    return run;
}

std::vector<views::Histogram> histograms_of(const std::string& folder, const std::string& name) {
    return views::read_descriptor(folder + "/descriptors/" + name + ".cfvd").histograms;
}

}  // namespace

TEST(CollectionIndex, QueriesGiveTheDistanceMatrixRowsMemberFirst) {
    const std::string folder = run_folder() + "/run/none";
    const CollectionIndex x = index_method_folder(folder, "none", 0);
    ASSERT_EQ(x.size(), 7u);
    EXPECT_EQ(x.views(), 66);
    EXPECT_EQ(x.method(), "none");
    EXPECT_GT(x.bytes(), 0u);
    const Eigen::MatrixXd D = io::read_distance_matrix(folder + "/distances.bin");
    for (std::size_t q = 0; q < x.size(); ++q) {
        const auto hist = histograms_of(folder, x.names()[q]);
        const std::vector<float> d = x.distances(hist, 2);
        for (std::size_t m = 0; m < x.size(); ++m) {
            // The matrix computes D(A, B) with the earlier model as A: exactly the query's value then,
            // the same up to the last bit of the double sum otherwise.
            if (m >= q) EXPECT_EQ(d[m], static_cast<float>(D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(m)))) << q << " " << m;
            else EXPECT_NEAR(d[m], D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(m)), 1e-6) << q << " " << m;
        }
        const auto top = x.top(hist, x.size(), 1);
        ASSERT_EQ(top.size(), x.size());
        EXPECT_EQ(top[0].model, q);
        EXPECT_EQ(top[0].distance, 0.f);
        EXPECT_EQ(top[0].name, x.names()[q]);
        std::vector<std::size_t> order(x.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(a)) < D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(b));
        });
        for (std::size_t r = 0; r < order.size(); ++r) EXPECT_EQ(top[r].model, order[r]) << "query " << q << " rank " << r;
        EXPECT_EQ(x.top(hist, 3, 2).size(), 3u);
    }
    // Threads do not change the answers.
    const auto hist = histograms_of(folder, x.names()[2]);
    EXPECT_EQ(x.distances(hist, 1), x.distances(hist, 2));
}

TEST(CollectionIndex, AQueryMeshFindsItselfThroughItsViews) {
    const std::string folder = run_folder() + "/run/none";
    const CollectionIndex x = index_method_folder(folder, "none", 0);
    const Mesh m = io::read_mesh(run_folder() + "/data/meshes/long-arms_1.ply");
    const auto hist = views::view_histograms(views::compute_views(m.V, m.F).features, x.codebook());
    const auto top = x.top(hist, 2, 2);
    EXPECT_EQ(top[0].name, "long-arms_1");
    EXPECT_EQ(top[0].cls, "long-arms");
    EXPECT_EQ(top[0].distance, 0.f);
    EXPECT_GT(top[1].distance, 0.f);
}

TEST(CollectionIndex, FileRoundTripAndRefusals) {
    const std::string folder = run_folder() + "/run/none";
    const CollectionIndex x = index_method_folder(folder, "euclidean-N:beta=65", 3000);
    const std::string path = folder + "/index_test.cfci";
    x.save(path);
    const CollectionIndex y = CollectionIndex::load(path);
    EXPECT_EQ(y.names(), x.names());
    EXPECT_EQ(y.classes(), x.classes());
    EXPECT_EQ(y.method(), "euclidean-N:beta=65");
    EXPECT_EQ(y.simplify(), 3000);
    EXPECT_EQ(y.bytes(), x.bytes());
    EXPECT_EQ(y.codebook().words(), x.codebook().words());
    const auto hist = histograms_of(folder, x.names()[4]);
    EXPECT_EQ(y.distances(hist, 2), x.distances(hist, 2));
    // Truncated, trailing bytes, not an index.
    const std::string bytes = io::read_file(path);
    io::write_file_atomic(path, bytes.substr(0, bytes.size() - 2));
    EXPECT_THROW(CollectionIndex::load(path), InputError);
    io::write_file_atomic(path, bytes + "xx");
    EXPECT_THROW(CollectionIndex::load(path), InputError);
    io::write_file_atomic(path, "CFVD" + bytes.substr(4));
    EXPECT_THROW(CollectionIndex::load(path), InputError);
    EXPECT_THROW(index_method_folder(folder + "_nothere", "none"), InputError);
    // Beyond 16 bits, a wrong view count.
    std::vector<std::vector<views::Histogram>> big(1, std::vector<views::Histogram>(66));
    big[0][0] = {{0, 70000.f}};
    EXPECT_THROW(CollectionIndex::build({"a"}, {"c"}, big, x.codebook(), "none"), InputError);
    big[0][0] = {{0, 3.f}};
    const CollectionIndex one = CollectionIndex::build({"a"}, {"c"}, big, x.codebook(), "none");
    EXPECT_THROW(one.distances(std::vector<views::Histogram>(65)), InputError);
    EXPECT_EQ(one.distances(big[0])[0], 0.f);
}
