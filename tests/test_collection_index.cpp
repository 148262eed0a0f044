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
#include "canonform/views/view_directions.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>

using namespace canonform;
using namespace canonform::retrieval;
using namespace canonform::canonical;
using namespace canonform::procedural;
namespace fs = std::filesystem;

namespace {

/// A finished `retrieve` run of seven figures (method none), made once per process.
const std::string& run_folder() {
    static const std::string run = [] {
        const std::string d = canonform::test::process_temp_path("canonform_test_index");
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
        // A query that names its place gets the matrix's values, bit for bit.
        const std::vector<float> own = x.distances(hist, 2, static_cast<std::ptrdiff_t>(q));
        for (std::size_t m = 0; m < x.size(); ++m) {
            const float matrix =
                static_cast<float>(D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(m)));
            // The matrix computes D(A, B) with the earlier model as A: exactly the query's value then,
            // the same up to the last bit of the double sum otherwise.
            if (m >= q)
                EXPECT_EQ(d[m], matrix) << q << " " << m;
            else
                EXPECT_NEAR(d[m], matrix, 1e-6) << q << " " << m;
            EXPECT_EQ(own[m], matrix) << q << " " << m;
        }
        const auto top = x.top(hist, x.size(), 1);
        ASSERT_EQ(top.size(), x.size());
        EXPECT_EQ(top[0].model, q);
        EXPECT_EQ(top[0].distance, 0.f);
        EXPECT_EQ(top[0].name, x.names()[q]);
        std::vector<std::size_t> order(x.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(a)) <
                   D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(b));
        });
        for (std::size_t r = 0; r < order.size(); ++r)
            EXPECT_EQ(top[r].model, order[r]) << "query " << q << " rank " << r;
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
    ASSERT_TRUE(y.first_pass().trained());
    EXPECT_EQ(y.first_pass().codes(), x.first_pass().codes());
    EXPECT_EQ(y.first_pass().axes(), x.first_pass().axes());
    EXPECT_EQ(y.code(hist), x.code(hist));
    for (std::size_t m = 0; m < x.size(); ++m)
        EXPECT_EQ(y.histograms(m), histograms_of(folder, x.names()[m]));
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

namespace {

/// A codebook of `words` random words (only its size matters to the index).
views::Codebook random_codebook(int words, unsigned seed) {
    std::mt19937 g(seed);
    views::DescriptorMatrix w(words, 128);
    for (Eigen::Index i = 0; i < w.size(); ++i) w.data()[i] = static_cast<float>(g() % 256);
    return views::Codebook::from_words(w);
}

/// `n` models of 66 views over `words` words: twelve prototypes (the same for every seed), each
/// model one of them with a share of its keypoints moved to random words, its views permuted by a
/// random cube rotation.
std::vector<std::vector<views::Histogram>> random_models(std::size_t n, int words, std::uint64_t seed,
                                                         std::vector<std::size_t>* rotation = nullptr) {
    std::mt19937_64 pg(static_cast<std::uint64_t>(words)), g(seed);  // the prototypes depend on `words` only
    const auto maps = views::rotation_view_maps();
    std::vector<std::vector<std::vector<int>>> protos(12, std::vector<std::vector<int>>(66));
    for (auto& p : protos)
        for (auto& v : p)
            for (int k = 0; k < 12; ++k)
                v.push_back(static_cast<int>(pg() % static_cast<std::uint64_t>(words)));
    std::vector<std::vector<views::Histogram>> out;
    for (std::size_t m = 0; m < n; ++m) {
        const auto& p = protos[g() % protos.size()];
        const std::size_t r = g() % maps.size();
        if (rotation) rotation->push_back(r);
        const double noise = 0.1 + 0.4 * static_cast<double>(g() % 1000) / 1000.0;
        std::vector<views::Histogram> model(66);
        for (int i = 0; i < 66; ++i) {
            std::vector<int> w;
            for (int word : p[static_cast<std::size_t>(i)])
                w.push_back(static_cast<double>(g() % 1000) / 1000.0 < noise
                                ? static_cast<int>(g() % static_cast<std::uint64_t>(words))
                                : word);
            model[static_cast<std::size_t>(maps[r][static_cast<std::size_t>(i)])] = views::histogram(w);
        }
        out.push_back(model);
    }
    return out;
}

std::vector<std::string> numbered(std::size_t n, const std::string& prefix) {
    std::vector<std::string> v;
    for (std::size_t k = 0; k < n; ++k) v.push_back(prefix + std::to_string(k));
    return v;
}

}  // namespace

TEST(CollectionIndex, PackedHistogramsRoundTripWithTheirEscapesAndGiveTheMatrix) {
    // Counts 1, 2..16 and beyond, word gaps up to 240, 256 and beyond, empty views.
    std::vector<std::vector<views::Histogram>> models = random_models(5, 1500, 3);
    models[0][0] = {{0, 1.f},    {240, 1.f},  {481, 1.f},   {482, 2.f},
                    {738, 16.f}, {995, 17.f}, {996, 300.f}, {1499, 1.f}};
    models[0][1] = {};
    models[1][5] = {{1499, 65000.f}};
    models[2][7] = {{0, 2.f}, {256, 2.f}, {513, 3.f}};
    const CollectionIndex x =
        CollectionIndex::build(numbered(5, "m"), numbered(5, "c"), models, random_codebook(1500, 1), "none");
    for (std::size_t m = 0; m < 5; ++m) EXPECT_EQ(x.histograms(m), models[m]) << m;
    const Eigen::MatrixXf D = views::distance_matrix(models, views::rotation_view_maps(), 1);
    for (std::size_t q = 0; q < 5; ++q) {
        const auto d = x.distances(models[q], 1, static_cast<std::ptrdiff_t>(q));
        for (std::size_t m = 0; m < 5; ++m)
            EXPECT_EQ(d[m], D(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(m))) << q << " " << m;
    }
    // Beyond 16 bits in a view's sum.
    models[3][0] = {{1, 40000.f}, {2, 30000.f}};
    EXPECT_THROW(
        CollectionIndex::build(numbered(5, "m"), numbered(5, "c"), models, random_codebook(1500, 1), "none"),
        InputError);
}

TEST(CollectionIndex, TwoStageQueriesReturnExactDistancesAndFindTheExactTopTen) {
    std::vector<std::size_t> rotation;
    const auto models = random_models(600, 200, 11, &rotation);
    const CollectionIndex x = CollectionIndex::build(numbered(600, "m"), numbered(600, "c"), models,
                                                     random_codebook(200, 2), "none");
    ASSERT_TRUE(x.first_pass().trained());
    EXPECT_EQ(x.first_pass().size(), 600u);
    // Small collections are searched exhaustively unless candidates are given.
    EXPECT_FALSE(x.two_stage({}));
    // The default candidate count never exceeds the collection.
    EXPECT_EQ(x.default_candidates(10), 600u);
    SearchOptions all;
    all.candidates = 600;
    EXPECT_TRUE(x.two_stage(all));
    const auto queries = random_models(40, 200, 12);
    double recall = 0;
    for (const auto& q : queries) {
        const auto exact = x.top(q, 10, 2);
        const auto full = x.search(q, 10, all);
        ASSERT_EQ(full.size(), exact.size());
        for (std::size_t r = 0; r < exact.size(); ++r) {
            EXPECT_EQ(full[r].model, exact[r].model);
            EXPECT_EQ(full[r].distance, exact[r].distance);
        }
        SearchOptions few;
        few.candidates = 100;
        few.threads = 1;
        const auto two = x.search(q, 10, few);
        few.threads = 2;
        const auto two2 = x.search(q, 10, few);
        const std::vector<float> d = x.distances(q, 1);
        ASSERT_EQ(two.size(), 10u);
        for (std::size_t r = 0; r < two.size(); ++r) {
            EXPECT_EQ(two[r].distance, d[two[r].model]);  // exact distances
            EXPECT_EQ(two2[r].model, two[r].model);       // whatever the threads
            if (r > 0) {
                EXPECT_TRUE(two[r - 1].distance < two[r].distance ||
                            (two[r - 1].distance == two[r].distance && two[r - 1].model < two[r].model));
            }
            for (const auto& e : exact) recall += e.model == two[r].model ? 0.1 / 40 : 0.0;
        }
    }
    // A sixth of the collection as candidates finds nearly all of the exact top 10.
    EXPECT_GT(recall, 0.9);
    // The first pass does not see the rotation clock matching undoes: each model's code is that
    // of its views put back in the prototype's order.
    const auto maps = views::rotation_view_maps();
    const std::vector<std::int8_t> codes = x.first_pass().codes();
    for (std::size_t m = 0; m < 20; ++m) {
        std::vector<views::Histogram> back(66);
        for (int i = 0; i < 66; ++i)
            back[static_cast<std::size_t>(i)] =
                models[m][static_cast<std::size_t>(maps[rotation[m]][static_cast<std::size_t>(i)])];
        EXPECT_EQ(x.code(back), x.code(models[m])) << m;
        const auto d = static_cast<std::size_t>(x.first_pass().dims());
        EXPECT_EQ(x.code(models[m]),
                  std::vector<std::int8_t>(codes.begin() + static_cast<std::ptrdiff_t>(m * d),
                                           codes.begin() + static_cast<std::ptrdiff_t>(m * d + d)));
    }
}

TEST(CollectionIndex, TopQueriesThatGiveUpFarModelsAnswerAsSortingEveryDistance) {
    // Twelve prototypes: a query's own prototype is near, the others far, so most models are
    // given up part way through their views; copies make ties, which go to the lower model.
    auto models = random_models(500, 200, 21);
    for (std::size_t m = 0; m < 60; ++m) models[440 + m] = models[m * 7];
    const CollectionIndex x = CollectionIndex::build(numbered(500, "m"), numbered(500, "c"), models,
                                                     random_codebook(200, 3), "none");
    auto queries = random_models(6, 200, 22);
    queries.push_back(models[7]);  // a member with copies of itself
    for (std::size_t q = 0; q < queries.size(); ++q)
        for (const std::ptrdiff_t self : {std::ptrdiff_t{-1}, std::ptrdiff_t{250}})
            for (const std::size_t k : {1u, 3u, 10u, 40u, 500u}) {
                const std::vector<float> d = x.distances(queries[q], 1, self);
                std::vector<std::size_t> order(d.size());
                std::iota(order.begin(), order.end(), std::size_t{0});
                std::stable_sort(order.begin(), order.end(),
                                 [&](std::size_t a, std::size_t b) { return d[a] < d[b]; });
                for (const int threads : {1, 2}) {
                    SearchOptions o;
                    o.exact = true;
                    o.threads = threads;
                    o.self = self;
                    const auto got = x.search(queries[q], k, o);
                    ASSERT_EQ(got.size(), k);
                    for (std::size_t r = 0; r < k; ++r) {
                        EXPECT_EQ(got[r].model, order[r]) << q << " " << self << " " << k << " " << r;
                        EXPECT_EQ(got[r].distance, d[order[r]]);
                    }
                    // The same through the first pass with every model a candidate.
                    o.exact = false;
                    o.candidates = 500;
                    const auto two = x.search(queries[q], k, o);
                    for (std::size_t r = 0; r < k; ++r) EXPECT_EQ(two[r].model, order[r]);
                }
            }
}

TEST(SummarySearch, TheViewsFallIntoFourOrbitsOfTheCubeRotations) {
    int count = 0;
    const auto orbit = view_orbits(views::rotation_view_maps(), 66, &count);
    ASSERT_EQ(count, 4);
    std::vector<int> sizes(4, 0);
    for (int o : orbit) ++sizes[static_cast<std::size_t>(o)];
    std::sort(sizes.begin(), sizes.end());
    EXPECT_EQ(sizes, (std::vector<int>{6, 12, 24, 24}));
    EXPECT_EQ(orbit[0], 0);
    EXPECT_THROW(view_orbits(views::rotation_view_maps(), 65), InputError);
}

TEST(SummarySearch, TheFirstAxisFollowsAPlantedDirectionAndTiesGoToTheLowerModel) {
    // 400 summaries of 300 coordinates: noise, plus a strong component along one direction u.
    std::mt19937_64 g(5);
    auto u01 = [&] { return static_cast<double>(g() >> 11) * 0x1.0p-53; };
    std::vector<double> u(300);
    double norm = 0;
    for (auto& v : u) {
        v = u01() - 0.5;
        norm += v * v;
    }
    for (auto& v : u) v /= std::sqrt(norm);
    std::vector<Summary> sample;
    for (int k = 0; k < 400; ++k) {
        Summary s;
        const double t = 10 * (u01() - 0.5);
        for (std::uint32_t j = 0; j < 300; ++j) {
            s.index.push_back(j);
            s.value.push_back(t * u[j] + 0.1 * (u01() - 0.5));
        }
        sample.push_back(s);
    }
    SummaryOptions o;
    o.dims = 16;
    const SummarySearch a = SummarySearch::train(sample, 300, o, 1),
                        b = SummarySearch::train(sample, 300, o, 2);
    EXPECT_EQ(a.axes(), b.axes());  // the same bits for any thread count
    double cosine = 0, length = 0;
    for (std::size_t j = 0; j < 300; ++j) {
        cosine += a.axes()[j * 16] * u[j];
        length += a.axes()[j * 16] * a.axes()[j * 16];
    }
    EXPECT_NEAR(length, 1.0, 1e-5);
    EXPECT_GT(std::abs(cosine), 0.999);
    // Codes: equal codes tie, the lower model first; the nearest code first.
    SummarySearch c = a;
    std::vector<std::int8_t> codes(5 * 16, 0);
    for (int k = 0; k < 16; ++k) codes[static_cast<std::size_t>(16 + k)] = 3;  // model 1 farther
    c.set_codes(codes);
    std::vector<std::int8_t> q(16, 0);
    EXPECT_EQ(c.nearest(q.data(), 3, 1), (std::vector<std::uint32_t>{0, 2, 3}));
    EXPECT_EQ(c.nearest(q.data(), 5, 2), (std::vector<std::uint32_t>{0, 2, 3, 4, 1}));
    EXPECT_THROW(SummarySearch::train({}, 300, o), InputError);
    o.dims = 20;
    EXPECT_THROW(SummarySearch::train(sample, 300, o), InputError);
}

TEST(SummarySearch, NearestCodesAreTheSmallestWholeDistancesWhateverTheSplit) {
    // nearest() reads every model's leading prefix_dims() bytes and the rest of a few: its answer
    // is that of sorting the whole distances, ties by the lower model, for any width and threads.
    std::mt19937_64 g(9);
    for (const int dims : {16, 48, 64, 128, 256}) {
        SummaryOptions o;
        o.dims = dims;
        SummarySearch s =
            SummarySearch::from_parts(o, static_cast<std::uint32_t>(dims),
                                      std::vector<float>(static_cast<std::size_t>(dims * dims), 0.f),
                                      std::vector<float>(static_cast<std::size_t>(dims), 0.f), 1.f);
        const std::size_t n = 9000;
        std::vector<std::int8_t> codes(n * static_cast<std::size_t>(dims));
        for (std::size_t m = 0; m < n; ++m)
            for (int k = 0; k < dims; ++k)  // narrow codes tie often; some models span the range
                codes[m * static_cast<std::size_t>(dims) + static_cast<std::size_t>(k)] =
                    static_cast<std::int8_t>(m % 5 == 0 ? static_cast<int>(g() % 255) - 127
                                                        : static_cast<int>(g() % 5) - 2);
        for (int k = 0; k < dims; ++k) {  // the extremes a file can hold: distance dims x 255^2
            codes[static_cast<std::size_t>(dims + k)] = -128;
            codes[static_cast<std::size_t>(2 * dims + k)] = 127;
        }
        s.set_codes(codes);
        ASSERT_EQ(s.size(), n);
        EXPECT_EQ(s.codes(), codes);
        for (const std::size_t from : {0u, 997u, 2u}) {
            const std::int8_t* q = codes.data() + from * static_cast<std::size_t>(dims);
            std::vector<std::pair<std::uint32_t, std::uint32_t>> all;
            for (std::size_t m = 0; m < n; ++m) {
                std::uint32_t d = 0;
                for (int k = 0; k < dims; ++k) {
                    const int e =
                        q[k] - codes[m * static_cast<std::size_t>(dims) + static_cast<std::size_t>(k)];
                    d += static_cast<std::uint32_t>(e * e);
                }
                all.emplace_back(d, static_cast<std::uint32_t>(m));
            }
            std::sort(all.begin(), all.end());
            for (const std::size_t count : {1u, 37u, 1000u, 9000u})
                for (const int threads : {1, 2}) {
                    const auto got = s.nearest(q, count, threads);
                    ASSERT_EQ(got.size(), count);
                    for (std::size_t r = 0; r < count; ++r)
                        ASSERT_EQ(got[r], all[r].second) << dims << " " << count << " " << r;
                }
        }
    }
}

TEST(CollectionIndex, ReadsVersionOneFilesAndAnswersExhaustively) {
    const auto models = random_models(30, 100, 21);
    const views::Codebook cb = random_codebook(100, 4);
    // The version 1 layout: entry offsets per view and (u16 word, u16 count) pairs.
    std::string b = "CFCI";
    auto put32 = [&](std::uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
    auto put_string = [&](const std::string& s) {
        put32(static_cast<std::uint32_t>(s.size()));
        b += s;
    };
    put32(1);
    put32(30);
    put32(66);
    put32(100);
    put_string("none");
    put32(0);
    for (std::size_t k = 0; k < 30; ++k) {
        put_string("m" + std::to_string(k));
        put_string("c");
    }
    b.append(reinterpret_cast<const char*>(cb.words().data()), 100 * 128 * sizeof(float));
    std::vector<std::uint64_t> offsets{0};
    std::vector<std::uint16_t> entries;
    for (const auto& m : models)
        for (const auto& h : m) {
            for (const auto& [w, c] : h) {
                entries.push_back(static_cast<std::uint16_t>(w));
                entries.push_back(static_cast<std::uint16_t>(c));
            }
            offsets.push_back(entries.size() / 2);
        }
    b.append(reinterpret_cast<const char*>(offsets.data()), offsets.size() * 8);
    b.append(reinterpret_cast<const char*>(entries.data()), entries.size() * 2);
    const std::string path =
        (fs::temp_directory_path() / ("canonform_test_v1_" + std::to_string(getpid()) + ".cfci")).string();
    io::write_file_atomic(path, b);
    const CollectionIndex x = CollectionIndex::load(path);
    fs::remove(path);
    ASSERT_EQ(x.size(), 30u);
    EXPECT_FALSE(x.first_pass().trained());
    SearchOptions o;
    o.candidates = 5;
    EXPECT_FALSE(x.two_stage(o));
    const CollectionIndex y =
        CollectionIndex::build(numbered(30, "m"), std::vector<std::string>(30, "c"), models, cb, "none");
    for (std::size_t m = 0; m < 30; ++m) EXPECT_EQ(x.histograms(m), models[m]);
    EXPECT_EQ(x.distances(models[3], 1), y.distances(models[3], 1));
    EXPECT_THROW(x.code(models[3]), InputError);
}
