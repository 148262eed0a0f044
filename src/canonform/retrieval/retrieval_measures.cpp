// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/retrieval/retrieval_measures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

namespace canonform::retrieval {

namespace {

/// Ranks of the other models (ascending distance, ties by index) and whether each is relevant.
std::vector<char> ranked_relevance(const Eigen::VectorXd& d, const std::vector<std::string>& labels, int q) {
    std::vector<int> order;
    for (int j = 0; j < static_cast<int>(d.size()); ++j)
        if (j != q) order.push_back(j);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return d(a) < d(b); });
    std::vector<char> rel;
    for (int j : order) rel.push_back(labels[static_cast<size_t>(j)] == labels[static_cast<size_t>(q)]);
    return rel;
}

void accumulate(Measures& sum, const Measures& m) {
    sum.nn += m.nn;
    sum.first_tier += m.first_tier;
    sum.second_tier += m.second_tier;
    sum.e_measure += m.e_measure;
    sum.dcg += m.dcg;
    sum.queries += 1;
}

Measures mean_of(Measures sum) {
    if (sum.queries == 0) return sum;
    const double n = sum.queries;
    sum.nn /= n;
    sum.first_tier /= n;
    sum.second_tier /= n;
    sum.e_measure /= n;
    sum.dcg /= n;
    return sum;
}

std::vector<double> recall_levels() {
    std::vector<double> r;
    for (int k = 1; k <= 20; ++k) r.push_back(0.05 * k);
    return r;
}

/// Precision at each recall level for one query (see the header).
std::vector<double> pr_curve(const std::vector<char>& rel, int relevant) {
    std::vector<double> hr, hp;  // recall and precision at each hit
    int hits = 0;
    for (size_t i = 0; i < rel.size() && hits < relevant; ++i)
        if (rel[i]) {
            ++hits;
            hr.push_back(static_cast<double>(hits) / relevant);
            hp.push_back(static_cast<double>(hits) / static_cast<double>(i + 1));
        }
    std::vector<double> out;
    for (double level : recall_levels()) {
        if (level <= hr.front() + 1e-12) {
            out.push_back(hp.front());
            continue;
        }
        size_t k = 1;
        while (k < hr.size() && hr[k] < level - 1e-12) ++k;
        if (k >= hr.size()) k = hr.size() - 1;
        const double t = (level - hr[k - 1]) / (hr[k] - hr[k - 1]);
        out.push_back(hp[k - 1] + std::clamp(t, 0.0, 1.0) * (hp[k] - hp[k - 1]));
    }
    return out;
}

}  // namespace

nlohmann::ordered_json to_json(const Measures& m) {
    return {{"nn", m.nn},
            {"first_tier", m.first_tier},
            {"second_tier", m.second_tier},
            {"e_measure", m.e_measure},
            {"dcg", m.dcg},
            {"queries", m.queries}};
}

Measures ranked_measures(const std::vector<char>& rel, int c1, int n) {
    Measures m;
    m.queries = 1;
    if (c1 <= 0) return m;
    m.nn = rel.empty() ? 0 : rel[0];
    auto hits_in = [&](int k) {
        return static_cast<double>(
            std::count(rel.begin(), rel.begin() + std::min<int>(k, static_cast<int>(rel.size())), 1));
    };
    m.first_tier = hits_in(c1) / c1;
    m.second_tier = hits_in(2 * c1) / c1;
    const int K = std::min(32, n - 1);
    const double h = hits_in(K);
    if (h > 0) {
        const double P = h / K, R = h / c1;
        m.e_measure = 2.0 / (1.0 / P + 1.0 / R);
    }
    double dcg = 0, ideal = 0;
    for (size_t i = 0; i < std::max(rel.size(), static_cast<size_t>(c1)); ++i) {
        const double w = i == 0 ? 1.0 : 1.0 / std::log2(static_cast<double>(i + 1));
        if (i < rel.size()) dcg += rel[i] * w;
        if (static_cast<int>(i) < c1) ideal += w;
    }
    m.dcg = dcg / ideal;
    return m;
}

Measures query_measures(const Eigen::VectorXd& d, const std::vector<std::string>& labels, int q) {
    const int c1 =
        static_cast<int>(std::count(labels.begin(), labels.end(), labels[static_cast<size_t>(q)])) - 1;
    return ranked_measures(ranked_relevance(d, labels, q), c1, static_cast<int>(labels.size()));
}

Evaluation evaluate(const Eigen::MatrixXd& D, const std::vector<std::string>& labels) {
    const Eigen::Index n = D.rows();
    if (D.cols() != n) throw InputError("the distance matrix must be square");
    if (static_cast<Eigen::Index>(labels.size()) != n)
        throw InputError("the distance matrix has " + std::to_string(n) + " rows but there are " +
                         std::to_string(labels.size()) + " labels");
    if (n < 2) throw InputError("at least two models are needed");
    if (!D.allFinite()) throw InputError("the distance matrix has NaN or infinite entries");
    std::map<std::string, int> size;
    for (const auto& l : labels) ++size[l];
    Evaluation e;
    e.recall = recall_levels();
    e.precision.assign(e.recall.size(), 0.0);
    std::map<std::string, Measures> sums;
    Measures micro;
    for (Eigen::Index q = 0; q < n; ++q) {
        const std::string& cls = labels[static_cast<size_t>(q)];
        if (size[cls] <= 2) continue;
        const Measures m = query_measures(D.row(q).transpose(), labels, static_cast<int>(q));
        accumulate(micro, m);
        accumulate(sums[cls], m);
        const auto pr =
            pr_curve(ranked_relevance(D.row(q).transpose(), labels, static_cast<int>(q)), size[cls] - 1);
        for (size_t k = 0; k < pr.size(); ++k) e.precision[k] += pr[k];
    }
    for (const auto& [cls, count] : size)
        if (count <= 2) e.skipped_classes.push_back(cls);
    if (micro.queries == 0) throw InputError("no class has more than two models: nothing to evaluate");
    for (auto& p : e.precision) p /= micro.queries;
    e.micro = mean_of(micro);
    Measures macro;
    for (const auto& [cls, sum] : sums) {
        e.classes.push_back(cls);
        e.per_class.push_back(mean_of(sum));
        accumulate(macro, e.per_class.back());
    }
    e.macro = mean_of(macro);
    e.macro.queries = micro.queries;
    return e;
}

int neighbours_needed(const std::vector<std::string>& labels) {
    std::map<std::string, int> size;
    for (const auto& l : labels) ++size[l];
    int largest = 0;
    for (const auto& [cls, count] : size) largest = std::max(largest, count);
    const int n = static_cast<int>(labels.size());
    return std::max(0, std::min(std::max(2 * largest, 32), n - 1));
}

NeighbourEvaluation evaluate_neighbours(const std::vector<std::vector<std::uint32_t>>& neighbours,
                                        const std::vector<std::string>& labels, int k) {
    const int n = static_cast<int>(labels.size());
    if (static_cast<int>(neighbours.size()) != n)
        throw InputError(std::to_string(neighbours.size()) + " neighbour lists but " + std::to_string(n) +
                         " labels");
    if (n < 2) throw InputError("at least two models are needed");
    std::map<std::string, int> size;
    int largest = 0;
    for (const auto& l : labels) largest = std::max(largest, ++size[l]);
    const int need = std::min(std::max(2 * (largest - 1), std::min(32, n - 1)), n - 1);
    if (k < need || k > n - 1)
        throw InputError(
            "neighbour lists of " + std::to_string(k) + " models: the measures need " + std::to_string(need) +
            " (twice the largest class less one, at least 32) and there are " + std::to_string(n - 1));
    NeighbourEvaluation out;
    out.k = k;
    Evaluation& e = out.evaluation;
    std::map<std::string, Measures> sums, bounds;
    Measures micro, bound;
    for (int q = 0; q < n; ++q) {
        const std::string& cls = labels[static_cast<size_t>(q)];
        const auto& list = neighbours[static_cast<size_t>(q)];
        if (static_cast<int>(list.size()) < k)
            throw InputError("the neighbour list of model " + std::to_string(q) + " has " +
                             std::to_string(list.size()) + " models, fewer than " + std::to_string(k));
        std::vector<char> rel;
        for (int i = 0; i < k; ++i) {
            const std::uint32_t m = list[static_cast<size_t>(i)];
            if (m >= static_cast<std::uint32_t>(n) || static_cast<int>(m) == q)
                throw InputError("the neighbour list of model " + std::to_string(q) + " names model " +
                                 std::to_string(m) + " (itself or out of range)");
            rel.push_back(labels[m] == cls);
        }
        if (size[cls] <= 2) continue;
        const int c1 = size[cls] - 1;
        const Measures m = ranked_measures(rel, c1, n);
        accumulate(micro, m);
        accumulate(sums[cls], m);
        // The relevant models beyond the K, each at rank K + 1 or later.
        double ideal = 0;
        for (int i = 0; i < c1; ++i) ideal += i == 0 ? 1.0 : 1.0 / std::log2(static_cast<double>(i + 1));
        const double missing = c1 - static_cast<double>(std::count(rel.begin(), rel.end(), 1));
        Measures b;
        b.dcg = missing / std::log2(static_cast<double>(k + 1)) / ideal;
        accumulate(bound, b);
        accumulate(bounds[cls], b);
    }
    for (const auto& [cls, count] : size)
        if (count <= 2) e.skipped_classes.push_back(cls);
    if (micro.queries == 0) throw InputError("no class has more than two models: nothing to evaluate");
    e.micro = mean_of(micro);
    out.dcg_bound = mean_of(bound);
    Measures macro;
    double macro_bound = 0;
    for (const auto& [cls, sum] : sums) {
        e.classes.push_back(cls);
        e.per_class.push_back(mean_of(sum));
        accumulate(macro, e.per_class.back());
        macro_bound += mean_of(bounds[cls]).dcg;
    }
    e.macro = mean_of(macro);
    e.macro.queries = micro.queries;
    out.dcg_bound_macro = macro_bound / static_cast<double>(sums.size());
    return out;
}

}  // namespace canonform::retrieval
