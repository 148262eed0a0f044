// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the CM-BOF view-descriptor core (SIFT: test_sift_features.cpp): codebook, bag-of-features
// distances, clock matching, the descriptor file. (Speed: bench/, never here.)
#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/sift_features.h"
#include "canonform/views/view_directions.h"

#include "test_util.h"

#include <gtest/gtest.h>

#ifndef CANONFORM_WITHOUT_FAISS
#include <faiss/Clustering.h>
#include <faiss/IndexFlat.h>
#include <faiss/utils/distances.h>
#endif

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <string>

using namespace canonform;
using namespace canonform::views;

namespace {

std::string temp_path(const std::string& name) {
    static const std::string dir = [] {
        const std::string d = canonform::test::process_temp_path("canonform_bof");
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir + "/" + name;
}

// 24 permutations of `views` views closed under inversion: identity, 11 random permutations, their
// 11 inverses, and the reversal (an involution). Stands in for the cube rotations' view maps.
std::vector<std::vector<int>> synthetic_maps(int views, std::uint64_t seed = 7) {
    std::mt19937_64 rng(seed);
    std::vector<std::vector<int>> maps;
    std::vector<int> id(views);
    std::iota(id.begin(), id.end(), 0);
    maps.push_back(id);
    for (int k = 0; k < 11; ++k) {
        std::vector<int> p = id;
        std::shuffle(p.begin(), p.end(), rng);
        std::vector<int> inv(views);
        for (int i = 0; i < views; ++i) inv[p[i]] = i;
        maps.push_back(p);
        maps.push_back(inv);
    }
    std::vector<int> rev(id.rbegin(), id.rend());
    maps.push_back(rev);
    return maps;
}

Histogram random_histogram(std::mt19937_64& rng, int words, int nnz_min, int nnz_max) {
    std::uniform_int_distribution<int> nnz_d(nnz_min, nnz_max), word_d(0, words - 1), count_d(1, 3);
    std::vector<int> w;
    const int nnz = nnz_d(rng);
    for (int k = 0; k < nnz; ++k) {
        const int word = word_d(rng), c = count_d(rng);
        for (int j = 0; j < c; ++j) w.push_back(word);
    }
    return histogram(w);
}

std::vector<Histogram> random_model(std::mt19937_64& rng, int views, int words, int nnz_min, int nnz_max) {
    std::vector<Histogram> m;
    for (int v = 0; v < views; ++v) m.push_back(random_histogram(rng, words, nnz_min, nnz_max));
    return m;
}

DescriptorMatrix random_descriptors(std::mt19937_64& rng, int n, int clusters = 0) {
    // SIFT-like values in [0, 255]; with clusters > 0, points scattered around `clusters` centres.
    std::uniform_real_distribution<float> u(0.f, 255.f);
    std::normal_distribution<float> g(0.f, 12.f);
    DescriptorMatrix centres(std::max(clusters, 1), 128);
    for (Eigen::Index i = 0; i < centres.size(); ++i) centres.data()[i] = u(rng);
    DescriptorMatrix X(n, 128);
    for (int i = 0; i < n; ++i) {
        if (clusters > 0) {
            const int c = static_cast<int>(rng() % static_cast<std::uint64_t>(clusters));
            for (int d = 0; d < 128; ++d) X(i, d) = std::clamp(centres(c, d) + g(rng), 0.f, 255.f);
        } else {
            for (int d = 0; d < 128; ++d) X(i, d) = u(rng);
        }
    }
    return X;
}

// A 256 x 256 8-bit depth image (0 = background, 255 = nearest) of a capsule stick figure, or, with
// bumps = true, a sphere with nine Gaussian bumps (orthographic height fields, no renderer).
double distortion(const DescriptorMatrix& X, const Codebook& cb) {
    const std::vector<int> a = cb.assign(X);
    double s = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) s += (X.row(i) - cb.words().row(a[i])).squaredNorm();
    return s;
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

}  // namespace

// ---- histograms and the view distance ---------------------------------------------------------------

TEST(BagOfFeatures, HistogramCountsSortedWords) {
    const Histogram h = histogram({5, 2, 5, 9, 2, 5});
    const Histogram expected = {{2, 2.f}, {5, 3.f}, {9, 1.f}};
    EXPECT_EQ(h, expected);
    EXPECT_TRUE(histogram({}).empty());
    EXPECT_THROW(histogram({1, -1}), InputError);
}

TEST(BagOfFeatures, ViewDistanceEqualDisjointEmpty) {
    const Histogram a = {{1, 2.f}, {4, 1.f}, {7, 3.f}};
    const Histogram b = {{0, 1.f}, {2, 5.f}};
    EXPECT_DOUBLE_EQ(view_distance(a, a), 0.0);
    EXPECT_DOUBLE_EQ(view_distance(a, b), 1.0);
    EXPECT_DOUBLE_EQ(view_distance({}, {}), 0.0);
    EXPECT_DOUBLE_EQ(view_distance(a, {}), 1.0);
    EXPECT_DOUBLE_EQ(view_distance({}, b), 1.0);
    // Hand value: a = {1:2, 4:1, 7:3} (sum 6), c = {1:1, 7:5} (sum 6): min-sum 1 + 3 = 4 -> 1 - 4/6.
    const Histogram c = {{1, 1.f}, {7, 5.f}};
    EXPECT_NEAR(view_distance(a, c), 1.0 - 4.0 / 6.0, 1e-12);
    // Different totals: max(sum) in the denominator. {1:2} vs {1:2, 3:2}: 1 - 2/4.
    EXPECT_NEAR(view_distance({{1, 2.f}}, {{1, 2.f}, {3, 2.f}}), 0.5, 1e-12);
}

TEST(BagOfFeatures, ViewDistanceSymmetricAndBounded) {
    std::mt19937_64 rng(3);
    for (int t = 0; t < 500; ++t) {
        const Histogram a = random_histogram(rng, 40, 0, 20), b = random_histogram(rng, 40, 0, 20);
        const double d = view_distance(a, b);
        EXPECT_GE(d, 0.0);
        EXPECT_LE(d, 1.0);
        EXPECT_DOUBLE_EQ(d, view_distance(b, a));
    }
}

// ---- clock matching -----------------------------------------------------------------------------------

TEST(BagOfFeatures, ClockMatchingRotatedCopyIsZero) {
    const int V = 66;
    const auto maps = synthetic_maps(V);
    std::mt19937_64 rng(11);
    const auto A = random_model(rng, V, 1500, 30, 100);
    for (int r : {0, 5, 23}) {
        std::vector<Histogram> B(V);
        for (int i = 0; i < V; ++i) B[maps[r][i]] = A[i];  // view i of A is seen as view maps[r][i] of B
        EXPECT_DOUBLE_EQ(clock_matching_distance(A, B, maps), 0.0) << "rotation " << r;
        EXPECT_DOUBLE_EQ(clock_matching_distance(B, A, maps), 0.0) << "rotation " << r;
        if (r != 0) {
            EXPECT_GT(clock_matching_distance(A, B, {maps[0]}), 1.0);  // without that rotation: not 0
        }
    }
    const auto C = random_model(rng, V, 1500, 30, 100);
    const double d = clock_matching_distance(A, C, maps);
    EXPECT_GT(d, 0.0);
    EXPECT_LE(d, V);
    EXPECT_DOUBLE_EQ(clock_matching_distance(A, A, maps), 0.0);
}

TEST(BagOfFeatures, ClockMatchingIsMinimumOverRotations) {
    const int V = 10;
    const auto maps = synthetic_maps(V, 99);
    std::mt19937_64 rng(5);
    const auto A = random_model(rng, V, 20, 1, 6), B = random_model(rng, V, 20, 1, 6);
    double best = 1e300;
    for (const auto& m : maps) {
        double s = 0;
        for (int i = 0; i < V; ++i) s += view_distance(A[i], B[m[i]]);
        best = std::min(best, s);
    }
    EXPECT_NEAR(clock_matching_distance(A, B, maps), best, 1e-12);
}

TEST(BagOfFeatures, ClockMatchingRejectsBadInput) {
    std::mt19937_64 rng(1);
    const auto A = random_model(rng, 4, 10, 1, 3), B = random_model(rng, 5, 10, 1, 3);
    const auto maps = synthetic_maps(4);
    EXPECT_THROW(clock_matching_distance(A, B, maps), InputError);            // view counts differ
    EXPECT_THROW(clock_matching_distance(A, A, {}), InputError);              // no maps
    EXPECT_THROW(clock_matching_distance(A, A, {{0, 1, 2}}), InputError);     // short map
    EXPECT_THROW(clock_matching_distance(A, A, {{0, 1, 2, 4}}), InputError);  // index out of range
    auto bad = A;
    bad[2] = {{3, 1.f}, {1, 1.f}};  // unsorted
    EXPECT_THROW(clock_matching_distance(bad, A, maps), InputError);
}

TEST(BagOfFeatures, DistanceMatrixMatchesPairwiseAndThreads) {
    const int V = 66, N = 17;  // 136 pairs: two workers (one per 64 pairs) when two threads are asked
    const auto maps = synthetic_maps(V);
    std::mt19937_64 rng(21);
    std::vector<std::vector<Histogram>> models;
    for (int m = 0; m < N; ++m) models.push_back(random_model(rng, V, 300, 0, 40));  // includes empty views
    models[3] = std::vector<Histogram>(V);                                           // a blank model
    const Eigen::MatrixXf D1 = distance_matrix(models, maps, 1), D2 = distance_matrix(models, maps, 2);
    EXPECT_EQ(D1, D2);
    for (int i = 0; i < N; ++i) {
        EXPECT_EQ(D1(i, i), 0.f);
        for (int j = 0; j < N; ++j) {
            EXPECT_EQ(D1(i, j), D1(j, i));
            if (i != j) {
                EXPECT_NEAR(D1(i, j), clock_matching_distance(models[i], models[j], maps), 1e-4);
            }
        }
    }
    EXPECT_NEAR(D1(3, 0), clock_matching_distance(models[3], models[0], maps), 1e-4);
}

// distance_rows() as its header defines it, one pair at a time: per rotation, per view i of A in
// order, the intersection with view j = maps[r][i] of B summed in float over B's entries in order,
// then D from it and the two totals (double), the rotations' sums over i in order.
float reference_distance(const std::vector<Histogram>& a, const std::vector<Histogram>& b,
                         const std::vector<std::vector<int>>& maps) {
    auto total = [](const Histogram& h) {
        double s = 0;
        for (const auto& e : h) s += e.second;
        return s;
    };
    double best = std::numeric_limits<double>::infinity();
    for (const auto& m : maps) {
        double s = 0;
        for (std::size_t i = 0; i < a.size(); ++i) {
            std::map<int, float> dense(a[i].begin(), a[i].end());
            const Histogram& bj = b[static_cast<std::size_t>(m[i])];
            float inter = 0.f;
            for (const auto& e : bj) {
                const auto it = dense.find(e.first);
                inter += std::min(it == dense.end() ? 0.f : it->second, e.second);
            }
            const double sa = total(a[i]), sb = total(bj);
            s += (sa <= 0 && sb <= 0) ? 0.0 : std::clamp(1.0 - inter / std::max(sa, sb), 0.0, 1.0);
        }
        best = std::min(best, s);
    }
    return static_cast<float>(best);
}

TEST(BagOfFeatures, DistanceRowsAreThePairAtATimeSumsBitForBit) {
    // Fractional counts (float sums that depend on their order), empty views, and three kinds of
    // maps: the cube rotations' (orbits of 24, 12, 8 and 6 views), permutations closed under
    // inversion, and maps that are neither (views that no rotation reaches, overlapping partners,
    // a view met by 40 others: more than 32 lanes).
    const int V = 66, N = 9;
    std::vector<std::vector<std::vector<int>>> kinds = {rotation_view_maps(), synthetic_maps(V)};
    std::mt19937_64 rng(31);
    std::vector<std::vector<int>> odd(5, std::vector<int>(V));
    for (auto& m : odd)
        for (int i = 0; i < V; ++i) m[i] = static_cast<int>(rng() % 20);  // views 20..65 never reached
    for (int i = 0; i < 40; ++i) odd[0][i] = 7;
    kinds.push_back(odd);
    // Models 0..4 random; 5..8 near copies of model 0 with large counts, whose distances are sums of
    // small terms 1 - inter / max, so that a float intersection summed in another order shows in
    // the result.
    std::uniform_real_distribution<float> frac(0.05f, 3.f), near(0.9999f, 1.0001f);
    std::vector<std::vector<Histogram>> models;
    for (int m = 0; m < N; ++m) {
        auto model = m < 5 ? random_model(rng, V, 400, 0, 60) : models[0];
        for (auto& h : model)
            for (auto& e : h) e.second *= m < 5 ? frac(rng) * 1e5f : near(rng);
        models.push_back(model);
    }
    for (const auto& maps : kinds) {
        const Eigen::MatrixXf D = distance_rows(models, maps, 0, N, 1);
        int differ = 0;
        for (int r = 0; r < N; ++r)
            for (int c = r + 1; c < N; ++c) {
                const float want = reference_distance(models[r], models[c], maps);
                differ += std::memcmp(&want, &D(r, c), sizeof want) != 0;
            }
        EXPECT_EQ(differ, 0) << maps.size() << " maps";
    }
}

// ---- codebook -----------------------------------------------------------------------------------------

TEST(Codebook, AssignIsNearestWord) {
    std::mt19937_64 rng(8);
    const DescriptorMatrix X = random_descriptors(rng, 5000), C = random_descriptors(rng, 300);
    const Codebook cb = Codebook::from_words(C);
    const std::vector<int> a = cb.assign(X);
    ASSERT_EQ(a.size(), 5000u);
    int exact = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        double best = 1e300;
        int arg = -1;
        for (Eigen::Index j = 0; j < C.rows(); ++j) {
            const double d = (X.row(i).cast<double>() - C.row(j).cast<double>()).squaredNorm();
            if (d < best) {
                best = d;
                arg = static_cast<int>(j);
            }
        }
        const double chosen = (X.row(i).cast<double>() - C.row(a[i]).cast<double>()).squaredNorm();
        EXPECT_LE(chosen, best * (1 + 1e-5) + 1e-3) << "descriptor " << i;
        exact += a[i] == arg;
    }
    EXPECT_GE(exact, 4990);  // ties within float rounding are the only allowed differences
}

TEST(Codebook, IntegerDescriptorsTakeTheNearestRoundedWordTiesToTheLowerIndex) {
    // SIFT descriptors (integers 0-255) meet the words rounded to 1/64 in exact integer sums, four
    // descriptors at a time (codebook.h): the word chosen is the lowest index among those with the
    // smallest |q|^2 - 128 x.q, found here by brute force in 64-bit integers. An odd number of
    // words (a last block of 16 words that is partly empty), duplicated words (ties), a last block
    // of fewer than four descriptors; every word search this CPU runs (portable, and avx512-vnni
    // where it can), each the same words.
    std::mt19937_64 rng(21);
    std::uniform_int_distribution<int> value(0, 255);
    std::uniform_real_distribution<float> word_value(0.f, 300.f);
    DescriptorMatrix X(1001, 128), C(301, 128);
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = static_cast<float>(value(rng));
    for (Eigen::Index i = 0; i < C.size(); ++i) C.data()[i] = word_value(rng);
    for (int k = 0; k < 20; ++k) C.row(100 + 10 * k) = C.row(7 * k);  // later copies of earlier words
    for (int k = 0; k < 5; ++k) C.row(290 + k) = X.row(k);            // words at some descriptors
    const Codebook cb = Codebook::from_words(C);
    const std::vector<int> got = cb.assign(X);
    ASSERT_EQ(got.size(), 1001u);
    const std::vector<std::string> paths = canonform::views::detail::word_search_paths();
    ASSERT_EQ(paths.front(), "portable");
    for (const std::string& path : paths)
        EXPECT_EQ(canonform::views::detail::assign_with(cb, X, path), got) << path;
    EXPECT_THROW(canonform::views::detail::assign_with(cb, X, "sse9"), canonform::InputError);
    std::vector<std::int64_t> q(static_cast<size_t>(C.size())), norm(static_cast<size_t>(C.rows()), 0);
    for (Eigen::Index w = 0; w < C.rows(); ++w)
        for (int c = 0; c < 128; ++c) {
            const size_t k = static_cast<size_t>(w * 128 + c);
            q[k] = std::lround(double(C(w, c)) * 64);
            norm[static_cast<size_t>(w)] += q[k] * q[k];
        }
    int differ = 0, tied = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        int arg = -1, ties = 0;
        for (Eigen::Index w = 0; w < C.rows(); ++w) {
            std::int64_t dot = 0;
            for (int c = 0; c < 128; ++c) dot += std::int64_t(X(i, c)) * q[static_cast<size_t>(w * 128 + c)];
            const std::int64_t score = norm[static_cast<size_t>(w)] - 128 * dot;
            if (score < best) {
                best = score;
                arg = static_cast<int>(w);
                ties = 0;
            } else if (score == best) {
                ++ties;
            }
        }
        differ += got[static_cast<size_t>(i)] != arg;
        tied += ties > 0;
    }
    EXPECT_EQ(differ, 0);
    EXPECT_GT(tied, 0);  // the duplicates were met and resolved to the lower index
}

TEST(Codebook, KMeansDeterministicAndBetterThanRandom) {
    std::mt19937_64 rng(9);
    const DescriptorMatrix X = random_descriptors(rng, 6000, 60);
    CodebookOptions o;
    o.words = 60;
    o.seed = 123;
    const Codebook a = Codebook::train(X, o), b = Codebook::train(X, o);
    ASSERT_EQ(a.size(), 60);
    EXPECT_TRUE(a.words() == b.words());
    o.seed = 124;
    const Codebook c = Codebook::train(X, o);
    EXPECT_FALSE(a.words() == c.words());
    o.method = CodebookOptions::Method::Random;
    const Codebook r1 = Codebook::train(X, o), r2 = Codebook::train(X, o);
    EXPECT_TRUE(r1.words() == r2.words());
    EXPECT_LT(distortion(X, a), distortion(X, r1));
}

#ifndef CANONFORM_WITHOUT_FAISS
// The kmeans method's nearest-word search (codebook_training.cpp) stands in for FAISS's exact index
// inside FAISS's k-means: the words must be FAISS's own, bit for bit. Once with small blocks of
// FAISS's products (its two block sizes are public settings) so that the descriptors and the words
// both come in several blocks with a remainder, on 37 words (five past the last eight) and on a
// collection of 30 distinct descriptors, so that some of the 37 first words coincide and their
// distances tie; once with blocks of 2,048 descriptors, which the search takes in two chunks of
// 1,024, and 2,500 descriptors (the last block, 452, whole).
TEST(Codebook, KMeansTakesTheWordsOfFaissOwnExactSearch) {
    const int query_bs = faiss::distance_compute_blas_query_bs;
    const int database_bs = faiss::distance_compute_blas_database_bs;
    std::mt19937_64 rng(31);
    const DescriptorMatrix clustered = random_descriptors(rng, 2000, 12);
    const DescriptorMatrix patterns = random_descriptors(rng, 30).array().round().matrix();
    DescriptorMatrix repeated(1500, kDescriptorSize);
    for (int i = 0; i < repeated.rows(); ++i) repeated.row(i) = patterns.row(static_cast<int>(rng() % 30));
    const DescriptorMatrix many = random_descriptors(rng, 2500, 40);
    struct Case {
        const DescriptorMatrix* X;
        int query_bs, database_bs;
        const char* name;
    };
    for (const Case& t : {Case{&clustered, 300, 16, "clustered"}, Case{&repeated, 300, 16, "repeated"},
                          Case{&many, 2048, database_bs, "chunks"}}) {
        faiss::distance_compute_blas_query_bs = t.query_bs;
        faiss::distance_compute_blas_database_bs = t.database_bs;
        CodebookOptions o;
        o.words = 37;
        o.seed = 8;
        o.sample = 0;
        const Codebook ours = Codebook::train(*t.X, o);
        // FAISS with its own index, set up as the kmeans method documents it (codebook.h): the
        // seed is the first draw of the method's stream when no sample is drawn.
        faiss::ClusteringParameters cp;
        cp.niter = o.kmeans_iterations;
        cp.seed = static_cast<int>(std::mt19937_64(o.seed)() % 2147483647u);
        cp.min_points_per_centroid = 1;
        cp.max_points_per_centroid = std::numeric_limits<int>::max() / 2;
        faiss::Clustering clustering(kDescriptorSize, o.words, cp);
        faiss::IndexFlatL2 index(kDescriptorSize);
        clustering.train(t.X->rows(), t.X->data(), index);
        const Eigen::Map<const DescriptorMatrix> theirs(clustering.centroids.data(), o.words,
                                                        kDescriptorSize);
        EXPECT_TRUE(ours.words() == theirs) << t.name;
    }
    faiss::distance_compute_blas_query_bs = query_bs;
    faiss::distance_compute_blas_database_bs = database_bs;
}
#endif

TEST(Codebook, EveryMethodDeterministicAndKMeansBeatsRandom) {
    std::mt19937_64 rng(19);
    const DescriptorMatrix X = random_descriptors(rng, 6000, 60);
    CodebookOptions o;
    o.words = 60;
    o.seed = 5;
    o.method = CodebookOptions::Method::Random;
    const double random = distortion(X, Codebook::train(X, o));
    for (const char* name : {"kmeans", "lloyd"}) {
        o.method = parse_codebook_method(name);
        EXPECT_EQ(codebook_method_name(o.method), name);
#ifdef CANONFORM_WITHOUT_FAISS  // the Windows build: kmeans is refused, naming the way out
        if (o.method == CodebookOptions::Method::KMeans) {
            EXPECT_EQ(CodebookOptions::kDefaultMethod, CodebookOptions::Method::Lloyd);
            EXPECT_NE(test::message_of([&] { Codebook::train(X, o); }).find("use 'lloyd'"),
                      std::string::npos);
            continue;
        }
#endif
        const Codebook a = Codebook::train(X, o), b = Codebook::train(X, o);
        EXPECT_TRUE(a.words() == b.words()) << name;
        // Both k-means reach a similar distortion, well below random words.
        EXPECT_LT(distortion(X, a), 0.8 * random) << name;
    }
    EXPECT_THROW(parse_codebook_method("kmedoids"), InputError);
}

TEST(Codebook, TrainsOnASeededSample) {
    std::mt19937_64 rng(20);
    const DescriptorMatrix X = random_descriptors(rng, 4000, 40);
    CodebookOptions o;
    o.words = 40;
    o.method = CodebookOptions::Method::Random;
    o.sample = 500;
    const Codebook a = Codebook::train(X, o), b = Codebook::train(X, o);
    EXPECT_TRUE(a.words() == b.words());
    // Every word is a training descriptor.
    for (Eigen::Index w = 0; w < a.size(); ++w) {
        bool found = false;
        for (Eigen::Index i = 0; i < X.rows() && !found; ++i) found = X.row(i) == a.words().row(w);
        EXPECT_TRUE(found) << "word " << w;
    }
    o.sample = 0;  // all descriptors: another draw
    EXPECT_FALSE(Codebook::train(X, o).words() == a.words());
    o.method = CodebookOptions::kDefaultMethod;  // kmeans (FAISS), or lloyd in a build without FAISS
    o.sample = 800;
    const Codebook k1 = Codebook::train(X, o), k2 = Codebook::train(X, o);
    EXPECT_TRUE(k1.words() == k2.words());
    EXPECT_LT(distortion(X, k1), distortion(X, a));  // k-means on a sample still beats random words
    o.sample = -1;
    EXPECT_THROW(Codebook::train(X, o), InputError);
}

TEST(Codebook, TrainingOnTheNamedRowsAloneGivesTheSameWords) {
    // What a sharded run's codebook stage does: it holds only the rows training_rows() names.
    std::mt19937_64 rng(21);
    const DescriptorMatrix X = random_descriptors(rng, 3000, 30);
    for (const auto method :
         {CodebookOptions::Method::Random, CodebookOptions::Method::Lloyd, CodebookOptions::kDefaultMethod})
        for (const std::int64_t sample : {std::int64_t(0), std::int64_t(700), std::int64_t(5000)}) {
            CodebookOptions o;
            o.words = 30;
            o.seed = 5;
            o.method = method;
            o.sample = sample;
            const std::vector<int> rows = Codebook::training_rows(X.rows(), o);
            EXPECT_EQ(rows.size(), sample == 700 ? 700u : 3000u);
            DescriptorMatrix S(static_cast<Eigen::Index>(rows.size()), 128);
            for (std::size_t i = 0; i < rows.size(); ++i)
                S.row(static_cast<Eigen::Index>(i)) = X.row(rows[i]);
            EXPECT_TRUE(Codebook::train_on_rows(S, X.rows(), o).words() == Codebook::train(X, o).words())
                << codebook_method_name(method) << " sample " << sample;
            EXPECT_THROW(Codebook::train_on_rows(S.topRows(S.rows() - 1), X.rows(), o), InputError);
        }
}

TEST(Codebook, FewerDescriptorsThanWordsIsRefusedWithBothNumbers) {
    std::mt19937_64 rng(10);
    const DescriptorMatrix X = random_descriptors(rng, 37);
    try {
        Codebook::train(X, {});  // 1500 words by default
        FAIL() << "a 1500-word codebook of 37 descriptors was trained";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("1500 words"), std::string::npos) << m;
        EXPECT_NE(m.find("only 37 training descriptors"), std::string::npos) << m;
        EXPECT_NE(m.find("--words"), std::string::npos) << m;
    }
    CodebookOptions o;
    o.words = 37;  // exactly as many: every descriptor is a word
    const Codebook cb = Codebook::train(X, o);
    EXPECT_EQ(cb.size(), 37);
    EXPECT_TRUE(cb.words() == X);
    EXPECT_THROW(Codebook::train(DescriptorMatrix(0, 128), {}), InputError);
}

TEST(Codebook, SaveLoadBitExactAndRejectsBadFiles) {
    std::mt19937_64 rng(12);
    DescriptorMatrix W = random_descriptors(rng, 50);
    W(3, 7) = 1e-30f;  // a denormal-adjacent value and a negative zero survive bit-exactly
    W(4, 0) = -0.0f;
    const Codebook cb = Codebook::from_words(W);
    const std::string path = temp_path("codebook.cfcb");
    cb.save(path);
    const Codebook back = Codebook::load(path);
    ASSERT_EQ(back.size(), 50);
    EXPECT_EQ(std::memcmp(back.words().data(), W.data(), sizeof(float) * W.size()), 0);
    EXPECT_EQ(back.assign(W), cb.assign(W));

    const std::string good = read_bytes(path);
    EXPECT_EQ(good.size(), 16u + 50u * 128u * 4u);
    canonform::test::fuzz_seed("codebook", "50_words.cfcb", good);
    canonform::test::fuzz_seed(
        "codebook", "3_words.cfcb",
        good.substr(0, 8) + std::string("\x03\0\0\0", 4) + good.substr(12, 4 + 3 * 128 * 4));
    canonform::test::fuzz_seed("codebook", "truncated.cfcb", good.substr(0, 100));
    const std::string bad = temp_path("bad.cfcb");
    write_bytes(bad, good.substr(0, good.size() - 3));  // truncated data
    EXPECT_THROW(Codebook::load(bad), InputError);
    write_bytes(bad, good.substr(0, 10));  // truncated header
    EXPECT_THROW(Codebook::load(bad), InputError);
    std::string magic = good;
    magic[0] = 'X';
    write_bytes(bad, magic);
    try {
        Codebook::load(bad);
        ADD_FAILURE() << "wrong magic accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos) << e.what();
    }
    std::string version = good;
    version[4] = 2;
    write_bytes(bad, version);
    EXPECT_THROW(Codebook::load(bad), InputError);
    write_bytes(bad, good + "x");  // trailing byte
    EXPECT_THROW(Codebook::load(bad), InputError);
    EXPECT_THROW(Codebook::load(temp_path("does_not_exist.cfcb")), InputError);
    std::filesystem::remove(path);
    std::filesystem::remove(bad);
}

// ---- descriptor file ----------------------------------------------------------------------------------

TEST(DescriptorFile, HistogramRoundTrip) {
    std::mt19937_64 rng(14);
    ModelDescriptor d;
    d.source = "meshes/cat0.ply \xc3\xa9";
    d.codebook_words = 1500;
    for (int v = 0; v < d.views; ++v) {
        d.histograms.push_back(v == 5 ? Histogram{} : random_histogram(rng, 1500, 1, 60));
        double s = 0;
        for (const auto& e : d.histograms.back()) s += e.second;
        d.keypoints_per_view.push_back(static_cast<int>(s));
    }
    const std::string path = temp_path("model.cfvd");
    write_descriptor(path, d);
    const ModelDescriptor r = read_descriptor(path);
    canonform::test::fuzz_seed("descriptor", "histograms.cfvd", read_bytes(path));
    EXPECT_EQ(r.version, 1);
    EXPECT_EQ(r.source, d.source);
    EXPECT_EQ(r.views, 66);
    EXPECT_EQ(r.image_size, 256);
    EXPECT_EQ(r.codebook_words, 1500);
    EXPECT_EQ(r.histograms, d.histograms);
    EXPECT_EQ(r.keypoints_per_view, d.keypoints_per_view);
    EXPECT_TRUE(r.raw.empty());

    // Inconsistent input is refused by the writer, and a damaged file by the reader.
    ModelDescriptor bad = d;
    bad.keypoints_per_view[0] += 1;
    EXPECT_THROW(write_descriptor(temp_path("bad.cfvd"), bad), InputError);
    bad = d;
    bad.histograms.pop_back();
    EXPECT_THROW(write_descriptor(temp_path("bad.cfvd"), bad), InputError);
    bad = d;
    bad.histograms[1].push_back({1500, 1.f});  // word outside the codebook
    bad.keypoints_per_view[1] += 1;
    EXPECT_THROW(write_descriptor(temp_path("bad.cfvd"), bad), InputError);

    const std::string good = read_bytes(path), badpath = temp_path("bad.cfvd");
    write_bytes(badpath, good.substr(0, good.size() - 1));
    EXPECT_THROW(read_descriptor(badpath), InputError);
    std::string m = good;
    m[3] = 'X';
    write_bytes(badpath, m);
    try {
        read_descriptor(badpath);
        ADD_FAILURE() << "wrong magic accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos) << e.what();
    }
    m = good;
    m[4] = 9;
    write_bytes(badpath, m);
    try {
        read_descriptor(badpath);
        ADD_FAILURE() << "version 9 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("version"), std::string::npos) << e.what();
    }
    write_bytes(badpath, good + std::string(4, '\0'));
    EXPECT_THROW(read_descriptor(badpath), InputError);
    // The first keypoint count sits at 24 + L; make it disagree with the histogram.
    m = good;
    m[24 + d.source.size()] = static_cast<char>(m[24 + d.source.size()] + 1);
    write_bytes(badpath, m);
    try {
        read_descriptor(badpath);
        ADD_FAILURE() << "inconsistent counts accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("inconsistent"), std::string::npos) << e.what();
    }
    for (std::size_t cut :
         {std::size_t(0), std::size_t(3), std::size_t(11), std::size_t(30), good.size() / 2}) {
        write_bytes(badpath, good.substr(0, cut));
        EXPECT_THROW(read_descriptor(badpath), InputError) << "cut at " << cut;
    }
    std::filesystem::remove(path);
    std::filesystem::remove(badpath);
}

TEST(DescriptorFile, RawRoundTrip) {
    std::mt19937_64 rng(15);
    ModelDescriptor d;
    d.views = 4;
    d.image_size = 128;
    d.source = "x";
    for (int v = 0; v < d.views; ++v) {
        d.raw.push_back(random_descriptors(rng, v == 2 ? 0 : 10 + v));
        d.keypoints_per_view.push_back(static_cast<int>(d.raw.back().rows()));
    }
    const std::string path = temp_path("raw.cfvd");
    write_descriptor(path, d);
    const ModelDescriptor r = read_descriptor(path);
    canonform::test::fuzz_seed("descriptor", "raw.cfvd", read_bytes(path));
    EXPECT_EQ(r.views, 4);
    EXPECT_EQ(r.image_size, 128);
    EXPECT_EQ(r.codebook_words, 0);
    EXPECT_TRUE(r.histograms.empty());
    ASSERT_EQ(r.raw.size(), 4u);
    for (int v = 0; v < 4; ++v) EXPECT_TRUE(r.raw[v] == d.raw[v]) << "view " << v;
    EXPECT_EQ(r.keypoints_per_view, d.keypoints_per_view);
    ModelDescriptor bad = d;
    bad.histograms.push_back({{0, 1.f}});  // both kinds of content
    EXPECT_THROW(write_descriptor(temp_path("bad_raw.cfvd"), bad), InputError);
    std::filesystem::remove(path);
}

TEST(DescriptorFile, AFolderGivenAsADescriptorOrCodebookIsNamedAsOne) {
    // Issue 11: a folder given as a descriptor or codebook file was "truncated, 0 bytes".
    const std::string dir = canonform::test::scratch_dir("folder_descriptor");
    std::filesystem::create_directories(dir + "/d.cfvd");
    std::filesystem::create_directories(dir + "/c.cfcb");
    EXPECT_NE(canonform::test::message_of([&] { read_descriptor(dir + "/d.cfvd"); }).find("is a folder"),
              std::string::npos);
    EXPECT_NE(canonform::test::message_of([&] { Codebook::load(dir + "/c.cfcb"); }).find("is a folder"),
              std::string::npos);
    EXPECT_NE(canonform::test::message_of([&] { read_descriptor(dir + "/none.cfvd"); }).find("no such file"),
              std::string::npos);
}
