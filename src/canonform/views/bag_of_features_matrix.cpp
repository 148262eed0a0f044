// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/bag_of_features.h"

#include "canonform/common/parallel.h"
#include "canonform/views/bag_of_features_checks.h"
#include "canonform/views/sift_simd.h"

#include <algorithm>
#include <limits>
#include <map>
#include <string>

// The distance matrix of bag_of_features.h, apart from the rest: it runs on the parallel loop
// (oneTBB), which a program that only computes descriptors - the view filter - does not need.
namespace canonform::views {
namespace {

using detail::check_histogram;
using detail::check_maps;
using detail::distance_from;
using detail::total;

// Clock matching of one model A (the row) against every later model B, arranged so that one pass
// over a view of B serves every view of A it is compared with. View j of B meets the views
// U_j = {i : maps[r][i] == j for some r} of A (for the 24 cube rotations, the orbit of j: 24, 12, 8
// or 6 views). A is held transposed, word by word: row w lists A's count of w in each view of U_j,
// for every distinct set U_j side by side (a block, padded to 8 lanes). Each entry (w, c) of B's
// view j then adds min(A's count, c) to all of U_j's intersections at once, 8 lanes a time. Each
// lane still sums its own pair's terms in the order of B's entries, from 0, in float: the same
// additions as one pair at a time, so the distances are the same bits.
struct Block {
    int start = 0;  // first lane in a transposed row
    int size = 0;   // lanes: the views of A in U_j, ascending
};

struct PairPlan {
    int stride = 0;                       // lanes in a transposed row (blocks padded to 8)
    std::vector<Block> blocks;            // the distinct sets U_j
    std::vector<int> block_of;            // per view j of B: its block, -1 if U_j is empty
    std::vector<int> first_pair;          // per view j of B: the pair index of its block's lane 0
    std::vector<std::vector<int>> place;  // per view i of A: its lanes in a transposed row
    std::vector<int> pair_of;             // views x R: pair index of (i, maps[r][i]) at i * R + r
    int rotations = 0, pairs = 0;
};

PairPlan plan_pairs(const std::vector<std::vector<int>>& maps, std::size_t views) {
    PairPlan p;
    const std::size_t R = maps.size();
    p.rotations = static_cast<int>(R);
    std::vector<std::vector<int>> users(views);
    for (const auto& m : maps)
        for (std::size_t i = 0; i < views; ++i)
            users[static_cast<std::size_t>(m[i])].push_back(static_cast<int>(i));
    std::map<std::vector<int>, int> known;
    p.block_of.assign(views, -1);
    p.first_pair.assign(views, 0);
    p.place.resize(views);
    for (std::size_t j = 0; j < views; ++j) {
        auto& u = users[j];
        std::sort(u.begin(), u.end());
        u.erase(std::unique(u.begin(), u.end()), u.end());
        p.first_pair[j] = p.pairs;
        p.pairs += static_cast<int>(u.size());
        if (u.empty()) continue;
        const auto [it, added] = known.emplace(u, static_cast<int>(p.blocks.size()));
        if (added) {
            for (std::size_t k = 0; k < u.size(); ++k)
                p.place[static_cast<std::size_t>(u[k])].push_back(p.stride + static_cast<int>(k));
            p.blocks.push_back({p.stride, static_cast<int>(u.size())});
            p.stride += static_cast<int>((u.size() + 7) / 8 * 8);
        }
        p.block_of[j] = it->second;
    }
    p.pair_of.resize(views * R);
    for (std::size_t i = 0; i < views; ++i)
        for (std::size_t r = 0; r < R; ++r) {
            const auto j = static_cast<std::size_t>(maps[r][i]);
            const auto& u = users[j];
            p.pair_of[i * R + r] =
                p.first_pair[j] +
                static_cast<int>(std::lower_bound(u.begin(), u.end(), static_cast<int>(i)) - u.begin());
        }
    return p;
}

// Model A transposed (words x plan.stride lanes) and its views' sums per lane.
struct DenseModel {
    std::vector<float> counts;
    std::vector<double> sums;
};

int max_word(const std::vector<Histogram>& m) {
    int w = -1;
    for (const auto& h : m)
        if (!h.empty()) w = std::max(w, h.back().first);
    return w;
}

void densify(const std::vector<Histogram>& m, const std::vector<double>& sums, int width,
             const PairPlan& plan, DenseModel& d) {
    const auto stride = static_cast<std::size_t>(plan.stride);
    d.counts.assign(static_cast<std::size_t>(width) * stride, 0.f);
    d.sums.assign(stride, 0.0);
    for (std::size_t i = 0; i < m.size(); ++i) {
        for (int lane : plan.place[i]) {
            d.sums[static_cast<std::size_t>(lane)] = sums[i];
            for (const auto& e : m[i])
                d.counts[static_cast<std::size_t>(e.first) * stride + static_cast<std::size_t>(lane)] =
                    e.second;
        }
    }
}

// out[k] = sum over b's entries (w, c), in order, of min(at[w * stride + k], c), for k < 8 K.
template <int K>
inline void intersect(const Histogram& b, const float* at, std::size_t stride, float* out) {
    using namespace sift;
    v8f acc[K] = {};
    for (const auto& e : b) {
        const float* q = at + static_cast<std::size_t>(e.first) * stride;
        const v8f c = splat8(e.second);
        for (int k = 0; k < K; ++k) {
            const v8f x = load8(q + 8 * k);
            acc[k] += c < x ? c : x;  // std::min(x, c)
        }
    }
    for (int k = 0; k < K; ++k) store8(out + 8 * k, acc[k]);
}

// Clock matching of A (densified) against B: pair distances into `pair`, then the smallest of the
// rotations' sums, each over the views in order (rotations side by side).
CANONFORM_CLONES double clock_dense(const DenseModel& A, const std::vector<Histogram>& B,
                                    const std::vector<double>& b_sums, const PairPlan& plan,
                                    std::vector<float>& inter, std::vector<double>& pair,
                                    std::vector<double>& rot) {
    const auto stride = static_cast<std::size_t>(plan.stride);
    inter.resize(stride);
    pair.resize(static_cast<std::size_t>(plan.pairs));
    for (std::size_t j = 0; j < B.size(); ++j) {
        const int bi = plan.block_of[j];
        if (bi < 0) continue;
        const Block& blk = plan.blocks[static_cast<std::size_t>(bi)];
        const int n = blk.size;
        for (int s = 0; s < n; s += 32) {
            const float* at = A.counts.data() + blk.start + s;
            float* out = inter.data() + s;
            switch (std::min(4, (n - s + 7) / 8)) {
                case 1:
                    intersect<1>(B[j], at, stride, out);
                    break;
                case 2:
                    intersect<2>(B[j], at, stride, out);
                    break;
                case 3:
                    intersect<3>(B[j], at, stride, out);
                    break;
                default:
                    intersect<4>(B[j], at, stride, out);
                    break;
            }
        }
        double* d = pair.data() + plan.first_pair[j];
        const double* sa = A.sums.data() + blk.start;
        for (int k = 0; k < n; ++k)
            d[k] = distance_from(inter[static_cast<std::size_t>(k)], sa[k], b_sums[j]);
    }
    const auto R = static_cast<std::size_t>(plan.rotations);
    rot.assign(R, 0.0);
    for (std::size_t i = 0; i < B.size(); ++i) {
        const int* po = plan.pair_of.data() + i * R;
        for (std::size_t r = 0; r < R; ++r) rot[r] += pair[static_cast<std::size_t>(po[r])];
    }
    double best = std::numeric_limits<double>::infinity();
    for (double s : rot) best = std::min(best, s);
    return best;
}

}  // namespace

Eigen::MatrixXf distance_rows(const std::vector<std::vector<Histogram>>& models,
                              const std::vector<std::vector<int>>& maps, std::size_t row_begin,
                              std::size_t row_end, int threads) {
    const std::size_t n = models.size();
    if (row_begin > row_end || row_end > n)
        throw InputError("Distance matrix: rows [" + std::to_string(row_begin) + ", " +
                         std::to_string(row_end) + ") are outside the " + std::to_string(n) + " models.");
    Eigen::MatrixXf D =
        Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(row_end - row_begin), static_cast<Eigen::Index>(n));
    if (n == 0) return D;
    const std::size_t views = models[0].size();
    if (views == 0) throw InputError("Distance matrix: model 0 has no views.");
    int width = 0;
    for (std::size_t m = 0; m < n; ++m) {
        if (models[m].size() != views)
            throw InputError("Distance matrix: model " + std::to_string(m) + " has " +
                             std::to_string(models[m].size()) + " views, model 0 has " +
                             std::to_string(views) + ".");
        for (std::size_t i = 0; i < views; ++i)
            check_histogram(models[m][i], ("model " + std::to_string(m)).c_str(), i);
        width = std::max(width, max_word(models[m]) + 1);
    }
    check_maps(maps, views);
    const PairPlan plan = plan_pairs(maps, views);
    std::vector<std::vector<double>> sums(n, std::vector<double>(views));
    for (std::size_t m = 0; m < n; ++m)
        for (std::size_t i = 0; i < views; ++i) sums[m][i] = total(models[m][i]);

    // Rows in parallel (row r computes the pairs (r, c > r)); dense scratch per worker. A worker
    // only for every kPairsPerWorker pairs: a pair costs tens of microseconds, starting a thread
    // about as much as a few pairs, so a handful of models is compared on the calling thread.
    constexpr std::size_t kPairsPerWorker = 64;
    std::size_t pairs = 0;
    for (std::size_t r = row_begin; r < row_end; ++r) pairs += n - r - 1;
    ParallelOptions par;
    par.threads = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(thread_count(threads)),
                                                         std::max<std::size_t>(1, pairs / kPairsPerWorker)));
    const auto rows = static_cast<std::ptrdiff_t>(row_end - row_begin);
    const int workers = parallel_workers(rows, par);
    struct Scratch {
        DenseModel row;
        std::vector<float> inter;
        std::vector<double> pair, rot;
    };
    std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
    parallel_for(
        rows,
        [&](std::ptrdiff_t row, int worker) {
            const auto r = row_begin + static_cast<std::size_t>(row);
            if (r + 1 >= n) return;
            Scratch& s = scratch[static_cast<std::size_t>(worker)];
            densify(models[r], sums[r], std::max(width, 1), plan, s.row);
            for (std::size_t c = r + 1; c < n; ++c)
                D(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(c)) =
                    static_cast<float>(clock_dense(s.row, models[c], sums[c], plan, s.inter, s.pair, s.rot));
        },
        par);
    return D;
}

Eigen::MatrixXf distance_matrix(const std::vector<std::vector<Histogram>>& models,
                                const std::vector<std::vector<int>>& maps, int threads) {
    Eigen::MatrixXf D = distance_rows(models, maps, 0, models.size(), threads);
    for (Eigen::Index r = 0; r < D.rows(); ++r)
        for (Eigen::Index c = r + 1; c < D.cols(); ++c) D(c, r) = D(r, c);
    return D;
}

}  // namespace canonform::views
