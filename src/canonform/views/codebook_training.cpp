// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/codebook.h"

#ifndef CANONFORM_WITHOUT_FAISS
#include <faiss/Clustering.h>
#include <faiss/IndexFlat.h>
#include <faiss/utils/distances.h>

#include <cstring>

// BLAS's single-precision product (the Fortran interface FAISS itself calls; 32-bit integers, as
// Debian's libblas.so.3 and OpenBLAS take them).
extern "C" int sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                      const float* alpha, const float* a, const int* lda, const float* b, const int* ldb,
                      const float* beta, float* c, const int* ldc);
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

// Codebook training (Codebook::train, train_on_rows, training_rows): in a library of its own,
// canonform::codebook_training, with FAISS (and through it BLAS and OpenMP), so that a program that
// only reads codebooks and assigns words - the view filter - needs none of them.
namespace canonform::views {
namespace {

// ---- random numbers (platform independent for a seed) ---------------------------------------------
double uniform01(std::mt19937_64& rng) {
    return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}
std::size_t uniform_index(std::mt19937_64& rng, std::size_t n) {
    return static_cast<std::size_t>(rng() % n);
}

// First `k` entries of a seeded partial Fisher-Yates shuffle of 0..n-1.
std::vector<int> sample_distinct(std::mt19937_64& rng, int n, int k) {
    std::vector<int> idx(n);
    std::iota(idx.begin(), idx.end(), 0);
    for (int i = 0; i < k; ++i)
        std::swap(idx[i], idx[i + uniform_index(rng, static_cast<std::size_t>(n - i))]);
    idx.resize(k);
    return idx;
}

DescriptorMatrix kmeans_pp_seed(const DescriptorMatrix& X, int k, std::mt19937_64& rng) {
    const int n = static_cast<int>(X.rows());
    const int m = std::min(n, 20 * k);
    std::vector<int> subset = sample_distinct(rng, n, m);
    DescriptorMatrix S(m, kDescriptorSize);
    for (int i = 0; i < m; ++i) S.row(i) = X.row(subset[i]);
    DescriptorMatrix C(k, kDescriptorSize);
    Eigen::VectorXd d2 = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
    int pick = static_cast<int>(uniform_index(rng, static_cast<std::size_t>(m)));
    for (int c = 0; c < k; ++c) {
        if (c > 0) {
            const double total = d2.sum();
            if (total > 0) {
                double u = uniform01(rng) * total, acc = 0;
                pick = m - 1;
                for (int i = 0; i < m; ++i) {
                    acc += d2[i];
                    if (acc > u && d2[i] > 0) {
                        pick = i;
                        break;
                    }
                }
            } else {
                pick = static_cast<int>(uniform_index(rng, static_cast<std::size_t>(m)));  // all duplicates
            }
        }
        C.row(c) = S.row(pick);
        const Eigen::VectorXf dn = (S.rowwise() - S.row(pick)).rowwise().squaredNorm();
        d2 = d2.cwiseMin(dn.cast<double>());
    }
    return C;
}

// The nearest word of every row of X and its squared distance (Codebook::assign's choice).
void nearest_words(const DescriptorMatrix& X, const DescriptorMatrix& C, std::vector<int>& label,
                   std::vector<float>* dist2) {
    label = Codebook::from_words(C).assign(X);
    if (!dist2) return;
    dist2->resize(label.size());
    for (size_t i = 0; i < label.size(); ++i)
        (*dist2)[i] = (X.row(static_cast<Eigen::Index>(i)) - C.row(label[i])).squaredNorm();
}

}  // namespace

namespace {

DescriptorMatrix lloyd(const DescriptorMatrix& X, int k, int iterations, std::mt19937_64& rng) {
    const int n = static_cast<int>(X.rows());
    DescriptorMatrix C = kmeans_pp_seed(X, k, rng);
    std::vector<int> label, previous;
    std::vector<float> dist2;
    for (int it = 0; it < iterations; ++it) {
        nearest_words(X, C, label, &dist2);
        if (label == previous) break;
        // New means, accumulated sequentially (deterministic).
        Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(k, kDescriptorSize);
        std::vector<int> count(static_cast<std::size_t>(k), 0);
        for (int i = 0; i < n; ++i) {
            sum.row(label[i]) += X.row(i).cast<double>();
            ++count[static_cast<std::size_t>(label[i])];
        }
        std::vector<int> order;  // points by decreasing distance, for re-seeding empty clusters
        std::size_t next_far = 0;
        for (int c = 0; c < k; ++c) {
            if (count[static_cast<std::size_t>(c)] > 0) {
                C.row(c) = (sum.row(c) / count[static_cast<std::size_t>(c)]).cast<float>();
                continue;
            }
            if (order.empty()) {
                order.resize(static_cast<std::size_t>(n));
                std::iota(order.begin(), order.end(), 0);
                std::stable_sort(order.begin(), order.end(),
                                 [&](int a, int b) { return dist2[a] > dist2[b]; });
            }
            C.row(c) = X.row(order[std::min(next_far++, order.size() - 1)]);
        }
        previous.swap(label);
    }
    return C;
}

#ifdef CANONFORM_WITHOUT_FAISS
DescriptorMatrix faiss_kmeans(const DescriptorMatrix&, int, int, std::uint64_t) {
    throw InputError(
        "Codebook: this build has no FAISS (CANONFORM_WITHOUT_FAISS: the Python wheel and the portable "
        "plugins leave it out), so no 'kmeans' method; use 'lloyd' (our own k-means) or 'random'.");
}
#else
// The nearest word of every training descriptor, for FAISS's k-means: the answer of FAISS's own
// exact search (IndexFlatL2, one neighbour), with the work that surrounds its products done in
// one pass on every core.
//
// FAISS (1.7.3, built for baseline x86-64 as Debian ships it) takes the inner products <x_i, c_j>
// with BLAS's sgemm, in blocks of distance_compute_blas_query_bs descriptors by
// distance_compute_blas_database_bs words; then, block by block, writes
// dis = (|x_i|^2 + |c_j|^2) - 2 <x_i, c_j> back over the products (a negative value clamped to
// 0), on all threads, and then scans them for the smallest on one thread, a value strictly
// smaller replacing the one held (ties to the lower word): two more passes over memory, the
// second on one core while the others wait (figures: docs/records/descriptor-speed.md).
//
// Here the same products (BLAS's sgemm, the same arguments but for the one departure below), the
// same norms (faiss::fvec_norms_L2sqr), the same distance expression and the same choice: the
// smallest distance, ties to the lower word, a NaN never chosen. Eight words at a time, each lane
// keeping its own smallest and the first word that reached it, then the lanes compared - which is
// the sequential scan's answer whatever the order the lanes ran in. The products of a block of
// descriptors sit in one buffer with every word of a descriptor side by side, and the distances
// and their minimum are taken in one pass, the descriptors shared between the threads.
// The departure: a block of FAISS's (4096 descriptors by default) is taken in chunks of kChunk
// descriptors, the last chunk taking the rest (kChunk to 2 kChunk - 1; a block of fewer than
// 2 kChunk is one call, FAISS's own), so that the products of a chunk stay in the cache
// (FAISS's 4096 x 1500 floats, 24 MB, did not: BLAS zeroes them before the product, and the pass
// above read them back from memory). A product <x_i, c_j> is the
// same whatever the number of descriptors in the call: BLAS sums each over the 128 values in one
// kernel whose order does not depend on the matrices' other sizes (OpenBLAS; the reference BLAS
// loops), and a call of kChunk descriptors or more never takes OpenBLAS's small-matrix kernels.
class NearestWordIndex final : public faiss::IndexFlatL2 {
public:
    // `training`: the descriptors FAISS's k-means searches in every iteration, whose norms are
    // then taken once (search() takes them again for any other descriptors).
    explicit NearestWordIndex(const DescriptorMatrix& training)
        : faiss::IndexFlatL2(kDescriptorSize), training_(training), training_norms_(training.rows()) {
        faiss::fvec_norms_L2sqr(training_norms_.data(), training.data(), kDescriptorSize,
                                static_cast<std::size_t>(training.rows()));
    }

    void search(std::int64_t n, const float* x, std::int64_t k, float* distances, std::int64_t* labels,
                const faiss::SearchParameters* params) const override {
        if (k != 1 || params != nullptr || ntotal == 0 || n < faiss::distance_compute_blas_threshold) {
            faiss::IndexFlatL2::search(n, x, k, distances, labels, params);
            return;
        }
        const int d = kDescriptorSize, words = static_cast<int>(ntotal);
        const float* c = get_xb();
        std::vector<float> c_norms(static_cast<std::size_t>(words));
        faiss::fvec_norms_L2sqr(c_norms.data(), c, d, static_cast<std::size_t>(words));
        const float* x_norms = training_norms_.data();
        if (x != training_.data() || n != training_.rows()) {
            x_norms_.resize(static_cast<std::size_t>(n));
            faiss::fvec_norms_L2sqr(x_norms_.data(), x, d, static_cast<std::size_t>(n));
            x_norms = x_norms_.data();
        }
        const std::int64_t bs_x = faiss::distance_compute_blas_query_bs;
        const int bs_y = faiss::distance_compute_blas_database_bs;
        products_.resize(static_cast<std::size_t>(std::min({bs_x, n, 2 * kChunk - 1})) *
                         static_cast<std::size_t>(words));
        const float one = 1, zero = 0;
        for (std::int64_t i0 = 0; i0 < n; i0 += bs_x) {
            const std::int64_t i1 = std::min(n, i0 + bs_x);
            for (std::int64_t c0 = i0, c1 = i0; c0 < i1; c0 = c1) {
                c1 = i1 - c0 >= 2 * kChunk ? c0 + kChunk : i1;
                const int nxi = static_cast<int>(c1 - c0);
                for (int j0 = 0; j0 < words; j0 += bs_y) {
                    const int nyi = std::min(words, j0 + bs_y) - j0;
                    sgemm_("Transpose", "Not transpose", &nyi, &nxi, &d, &one,
                           c + static_cast<std::size_t>(j0) * d, &d, x + static_cast<std::size_t>(c0) * d, &d,
                           &zero, products_.data() + j0, &words);
                }
#pragma omp parallel for schedule(static)
                for (std::int64_t i = c0; i < c1; ++i)
                    nearest(
                        products_.data() + static_cast<std::size_t>(i - c0) * static_cast<std::size_t>(words),
                        c_norms.data(), words, x_norms[i], distances[i], labels[i]);
            }
        }
    }

private:
    // Descriptors per product call within one of FAISS's blocks (below).
    static constexpr std::int64_t kChunk = 1024;

    using v4f = float __attribute__((vector_size(16)));
    using v4i = std::int32_t __attribute__((vector_size(16)));

    // One lane set: four words side by side, each lane keeping its smallest and the first word
    // that reached it.
    struct Lanes {
        v4f best = v4f{} + HUGE_VALF;
        v4i word = {};
        void take(const float* ip, const float* cn, v4f xn, v4i at) {
            v4f p, y;
            std::memcpy(&p, ip, sizeof p);
            std::memcpy(&y, cn, sizeof y);
            v4f dis = (xn + y) - (v4f{} + 2.0f) * p;
            dis = dis < v4f{} ? v4f{} : dis;
            const v4i smaller = dis < best;
            best = smaller ? dis : best;
            word = smaller ? at : word;
        }
        void fold(float& b, std::int32_t& bj) const {
            for (int l = 0; l < 4; ++l)
                if (best[l] < b || (best[l] == b && word[l] < bj)) {
                    b = best[l];
                    bj = word[l];
                }
        }
    };

    // The smallest of dis_j = (xn + cn[j]) - 2 ip[j] (negative -> 0) over j < words, and its j
    // (the lowest of equal ones); infinity and 0 if every one is NaN or infinite. Two lane sets,
    // eight words a step: baseline x86-64 has four float lanes per register.
    static void nearest(const float* ip, const float* cn, int words, float xn, float& best,
                        std::int64_t& label) {
        float b = HUGE_VALF;
        std::int32_t bj = 0;
        int j = 0;
        if (words >= 8) {
            const v4f vx = v4f{} + xn;
            Lanes low, high;
            v4i at = {0, 1, 2, 3};
            for (; j + 8 <= words; j += 8, at += 8) {
                low.take(ip + j, cn + j, vx, at);
                high.take(ip + j + 4, cn + j + 4, vx, at + 4);
            }
            low.fold(b, bj);
            high.fold(b, bj);
        }
        for (; j < words; ++j) {
            float dis = (xn + cn[j]) - 2 * ip[j];
            if (dis < 0) dis = 0;
            if (dis < b) {
                b = dis;
                bj = j;
            }
        }
        best = b;
        label = bj;
    }

    const DescriptorMatrix& training_;
    std::vector<float> training_norms_;
    mutable std::vector<float> x_norms_, products_;  // scratch of search(), kept between iterations
};

DescriptorMatrix faiss_kmeans(const DescriptorMatrix& X, int k, int iterations, std::uint64_t seed) {
    faiss::ClusteringParameters cp;
    cp.niter = iterations;
    cp.seed = static_cast<int>(seed % 2147483647u);
    cp.verbose = false;
    cp.min_points_per_centroid = 1;  // no warning for small inputs (n > k is guaranteed)
    cp.max_points_per_centroid = std::numeric_limits<int>::max() / 2;  // we sample ourselves
    faiss::Clustering clustering(kDescriptorSize, k, cp);
    NearestWordIndex index(X);
    // FAISS indices are int64_t: faiss::Index::idx_t up to 1.7.3 (bookworm), faiss::idx_t after.
    clustering.train(static_cast<std::int64_t>(X.rows()), X.data(), index);
    if (clustering.centroids.size() != static_cast<std::size_t>(k) * kDescriptorSize)
        throw NumericalError("Codebook: FAISS k-means returned " +
                             std::to_string(clustering.centroids.size() / kDescriptorSize) +
                             " words, expected " + std::to_string(k) + ".");
    return Eigen::Map<const DescriptorMatrix>(clustering.centroids.data(), k, kDescriptorSize);
}
#endif

}  // namespace

namespace {

void check_options(const CodebookOptions& options, std::int64_t total) {
    if (options.words <= 0) throw InputError("Codebook: the number of words must be positive.");
    if (options.kmeans_iterations < 0) throw InputError("Codebook: kmeans_iterations must be >= 0.");
    if (options.sample < 0)
        throw InputError("Codebook: the training sample must be >= 0 (0 = every descriptor).");
    if (total == 0) throw InputError("Codebook: no training descriptors (every view was blank?).");
    if (total > std::numeric_limits<int>::max()) throw InputError("Codebook: too many training descriptors.");
    // Never fewer words than asked for, silently: a codebook of every descriptor is not what was asked.
    if (total < options.words)
        throw InputError("Codebook: " + std::to_string(options.words) +
                         " words asked for, but there are only " + std::to_string(total) +
                         " training descriptors: ask for at most " + std::to_string(total) +
                         " words (--words in the canonform tool), or train on more meshes.");
}

bool draws_sample(const CodebookOptions& options, std::int64_t total) {
    return total > options.words && options.sample > 0 && options.sample < total;
}

// The sample of training_rows(), drawn from `rng` (which train_on_rows() continues).
std::vector<int> draw_sample(std::mt19937_64& rng, int n, const CodebookOptions& options) {
    const int m = static_cast<int>(std::max<std::int64_t>(options.sample, options.words + 1));
    return sample_distinct(rng, n, std::min(m, n));
}

}  // namespace

std::vector<int> Codebook::training_rows(std::int64_t total, const CodebookOptions& options) {
    check_options(options, total);
    const int n = static_cast<int>(total);
    if (!draws_sample(options, total)) {
        std::vector<int> all(static_cast<std::size_t>(n));
        std::iota(all.begin(), all.end(), 0);
        return all;
    }
    std::mt19937_64 rng(options.seed);
    return draw_sample(rng, n, options);
}

Codebook Codebook::train(const DescriptorMatrix& X, const CodebookOptions& options) {
    check_options(options, X.rows());
    if (!X.allFinite()) throw InputError("Codebook: a training descriptor has a non-finite value.");
    if (!draws_sample(options, X.rows())) return train_on_rows(X, X.rows(), options);
    const std::vector<int> pick = training_rows(X.rows(), options);
    DescriptorMatrix sampled(static_cast<Eigen::Index>(pick.size()), kDescriptorSize);
    for (std::size_t i = 0; i < pick.size(); ++i) sampled.row(static_cast<Eigen::Index>(i)) = X.row(pick[i]);
    return train_on_rows(sampled, X.rows(), options);
}

Codebook Codebook::train_on_rows(const DescriptorMatrix& S, std::int64_t total,
                                 const CodebookOptions& options) {
    check_options(options, total);
    if (!S.allFinite()) throw InputError("Codebook: a training descriptor has a non-finite value.");
    const int n = static_cast<int>(total), k = options.words;
    std::mt19937_64 rng(options.seed);
    const bool sampled = draws_sample(options, total);
    if (sampled) draw_sample(rng, n, options);  // the same draws, so that rng continues alike
    const std::int64_t expected =
        sampled ? std::min<std::int64_t>(std::max<std::int64_t>(options.sample, k + 1), n) : n;
    if (static_cast<std::int64_t>(S.rows()) != expected)
        throw InputError("Codebook: " + std::to_string(S.rows()) +
                         " training rows given, training_rows() names " + std::to_string(expected) + ".");
    if (n == k) return from_words(S);  // exactly as many descriptors as words: each is a word
    const int m = static_cast<int>(S.rows());

    switch (options.method) {
        case CodebookOptions::Method::Random: {
            const std::vector<int> pick = sample_distinct(rng, m, k);
            DescriptorMatrix C(k, kDescriptorSize);
            for (int i = 0; i < k; ++i) C.row(i) = S.row(pick[i]);
            return from_words(std::move(C));
        }
        case CodebookOptions::Method::Lloyd:
            return from_words(lloyd(S, k, options.kmeans_iterations, rng));
        case CodebookOptions::Method::KMeans:
            if (options.kmeans_iterations == 0) {  // FAISS's initialisation alone: random sample points
                const std::vector<int> pick = sample_distinct(rng, m, k);
                DescriptorMatrix C(k, kDescriptorSize);
                for (int i = 0; i < k; ++i) C.row(i) = S.row(pick[i]);
                return from_words(std::move(C));
            }
            return from_words(faiss_kmeans(S, k, options.kmeans_iterations, rng()));
    }
    throw InputError("Codebook: unknown method.");
}

}  // namespace canonform::views
