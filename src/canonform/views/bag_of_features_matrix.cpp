// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/bag_of_features.h"

#include "canonform/common/parallel.h"
#include "canonform/views/bag_of_features_checks.h"

#include <algorithm>
#include <limits>
#include <string>

// The distance matrix of bag_of_features.h, apart from the rest: it runs on the parallel loop
// (oneTBB), which a program that only computes descriptors - the view filter - does not need.
namespace canonform::views {
namespace {

using detail::check_histogram;
using detail::check_maps;
using detail::distance_from;
using detail::total;

// The distinct (i, j) pairs used by the maps, and per rotation the pair index of each view.
struct PairPlan {
    std::vector<std::vector<int>> partners;  // partners[i] = distinct j's of view i
    std::vector<std::vector<int>> pair_of;   // pair_of[r][i] = index into the flat pair list
    int pairs = 0;
};

PairPlan plan_pairs(const std::vector<std::vector<int>>& maps, std::size_t views) {
    PairPlan p;
    p.partners.resize(views);
    std::vector<std::vector<int>> offset(views);
    for (std::size_t i = 0; i < views; ++i) {
        for (const auto& m : maps) p.partners[i].push_back(m[i]);
        std::sort(p.partners[i].begin(), p.partners[i].end());
        p.partners[i].erase(std::unique(p.partners[i].begin(), p.partners[i].end()), p.partners[i].end());
    }
    std::vector<int> base(views + 1, 0);
    for (std::size_t i = 0; i < views; ++i) base[i + 1] = base[i] + static_cast<int>(p.partners[i].size());
    p.pairs = base[views];
    p.pair_of.assign(maps.size(), std::vector<int>(views));
    for (std::size_t r = 0; r < maps.size(); ++r)
        for (std::size_t i = 0; i < views; ++i) {
            const auto& q = p.partners[i];
            p.pair_of[r][i] =
                base[i] + static_cast<int>(std::lower_bound(q.begin(), q.end(), maps[r][i]) - q.begin());
        }
    return p;
}

// Dense copies of a model's views (views x (max word + 1)), for the scatter-gather intersection.
struct DenseModel {
    int width = 0;
    std::vector<float> values;  // views * width
    std::vector<double> sums;
};

int max_word(const std::vector<Histogram>& m) {
    int w = -1;
    for (const auto& h : m)
        if (!h.empty()) w = std::max(w, h.back().first);
    return w;
}

void densify(const std::vector<Histogram>& m, int width, DenseModel& d) {
    d.width = width;
    d.values.assign(m.size() * static_cast<std::size_t>(width), 0.f);
    d.sums.resize(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) {
        float* row = d.values.data() + i * static_cast<std::size_t>(width);
        for (const auto& e : m[i]) row[e.first] = e.second;
        d.sums[i] = total(m[i]);
    }
}

// Clock matching of dense A against sparse B with a prepared plan; `scratch` holds pair distances.
double clock_dense(const DenseModel& A, const std::vector<Histogram>& B, const std::vector<double>& b_sums,
                   const PairPlan& plan, std::vector<double>& scratch) {
    scratch.resize(static_cast<std::size_t>(plan.pairs));
    const std::size_t views = B.size();
    std::size_t k = 0;
    for (std::size_t i = 0; i < views; ++i) {
        const float* row = A.values.data() + i * static_cast<std::size_t>(A.width);
        for (int j : plan.partners[i]) {
            float inter = 0.f;
            for (const auto& e : B[static_cast<std::size_t>(j)])
                if (e.first < A.width) inter += std::min(row[e.first], e.second);
            scratch[k++] = distance_from(inter, A.sums[i], b_sums[static_cast<std::size_t>(j)]);
        }
    }
    double best = std::numeric_limits<double>::infinity();
    for (const auto& pr : plan.pair_of) {
        double s = 0;
        for (int q : pr) s += scratch[static_cast<std::size_t>(q)];
        best = std::min(best, s);
    }
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
    std::vector<DenseModel> dense(static_cast<std::size_t>(workers));
    std::vector<std::vector<double>> scratch(static_cast<std::size_t>(workers));
    parallel_for(
        rows,
        [&](std::ptrdiff_t row, int worker) {
            const auto r = row_begin + static_cast<std::size_t>(row);
            if (r + 1 >= n) return;
            DenseModel& A = dense[static_cast<std::size_t>(worker)];
            densify(models[r], std::max(width, 1), A);
            for (std::size_t c = r + 1; c < n; ++c)
                D(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(c)) = static_cast<float>(
                    clock_dense(A, models[c], sums[c], plan, scratch[static_cast<std::size_t>(worker)]));
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
