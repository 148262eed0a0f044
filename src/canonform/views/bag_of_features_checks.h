// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: checks and small helpers shared by bag_of_features.cpp and bag_of_features_matrix.cpp
// (private to the views library; the algorithms are documented in bag_of_features.h).
#pragma once

#include "canonform/views/bag_of_features.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace canonform::views {
namespace detail {

/// Sum of a histogram's counts.
double total(const Histogram& h);
/// D(a, b) from the intersection and the two totals (empty cases as in bag_of_features.h).
inline double distance_from(double inter, double sa, double sb) {
    if (sa <= 0 && sb <= 0) return 0.0;  // both empty
    const double m = std::max(sa, sb);
    return std::clamp(1.0 - inter / m, 0.0, 1.0);
}
/// InputError unless h is sorted by strictly increasing word with positive finite counts.
void check_histogram(const Histogram& h, const char* which, std::size_t view);
/// InputError unless every map lists `views` view indices in [0, views).
void check_maps(const std::vector<std::vector<int>>& maps, std::size_t views);

}  // namespace detail
}  // namespace canonform::views
