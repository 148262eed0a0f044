// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/bag_of_features.h"

#include "canonform/views/bag_of_features_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace canonform::views {
namespace detail {

double total(const Histogram& h) {
    double s = 0;
    for (const auto& e : h) s += e.second;
    return s;
}

void check_histogram(const Histogram& h, const char* which, std::size_t view) {
    int last = -1;
    for (const auto& e : h) {
        if (e.first <= last)
            throw InputError(std::string("Bag of features: histogram of view ") + std::to_string(view) +
                             " of " + which +
                             " is not sorted by strictly increasing word (or has a negative word).");
        if (!(e.second > 0) || !std::isfinite(e.second))
            throw InputError(std::string("Bag of features: histogram of view ") + std::to_string(view) +
                             " of " + which + " has a non-positive or non-finite count.");
        last = e.first;
    }
}

void check_maps(const std::vector<std::vector<int>>& maps, std::size_t views) {
    if (maps.empty()) throw InputError("Clock matching: no rotation maps given.");
    for (std::size_t r = 0; r < maps.size(); ++r) {
        if (maps[r].size() != views)
            throw InputError("Clock matching: rotation map " + std::to_string(r) + " has " +
                             std::to_string(maps[r].size()) + " entries, the models have " +
                             std::to_string(views) + " views.");
        for (int j : maps[r])
            if (j < 0 || static_cast<std::size_t>(j) >= views)
                throw InputError("Clock matching: rotation map " + std::to_string(r) +
                                 " has the view index " + std::to_string(j) + ", outside [0, " +
                                 std::to_string(views) + ").");
    }
}

}  // namespace detail

using detail::check_histogram;
using detail::check_maps;
using detail::distance_from;

Histogram histogram(const std::vector<int>& words) {
    std::vector<int> w = words;
    for (int x : w)
        if (x < 0) throw InputError("Bag of features: negative word index " + std::to_string(x) + ".");
    std::sort(w.begin(), w.end());
    Histogram h;
    for (std::size_t k = 0; k < w.size();) {
        std::size_t e = k;
        while (e < w.size() && w[e] == w[k]) ++e;
        h.emplace_back(w[k], static_cast<float>(e - k));
        k = e;
    }
    return h;
}

double view_distance(const Histogram& a, const Histogram& b) {
    double inter = 0, sa = 0, sb = 0;
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (a[i].first < b[j].first)
            sa += a[i++].second;
        else if (b[j].first < a[i].first)
            sb += b[j++].second;
        else {
            inter += std::min(a[i].second, b[j].second);
            sa += a[i++].second;
            sb += b[j++].second;
        }
    }
    for (; i < a.size(); ++i) sa += a[i].second;
    for (; j < b.size(); ++j) sb += b[j].second;
    return distance_from(inter, sa, sb);
}

double clock_matching_distance(const std::vector<Histogram>& a, const std::vector<Histogram>& b,
                               const std::vector<std::vector<int>>& maps) {
    if (a.size() != b.size())
        throw InputError("Clock matching: the models have different view counts (" +
                         std::to_string(a.size()) + " and " + std::to_string(b.size()) + ").");
    if (a.empty()) throw InputError("Clock matching: the models have no views.");
    check_maps(maps, a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        check_histogram(a[i], "model A", i);
        check_histogram(b[i], "model B", i);
    }
    double best = std::numeric_limits<double>::infinity();
    for (const auto& m : maps) {
        double s = 0;
        for (std::size_t i = 0; i < a.size(); ++i)
            s += view_distance(a[i], b[static_cast<std::size_t>(m[i])]);
        best = std::min(best, s);
    }
    return best;
}

}  // namespace canonform::views
