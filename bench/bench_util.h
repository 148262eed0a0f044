// SPDX-License-Identifier: GPL-3.0-or-later
// canonform benchmarks: small helpers shared by the bench programs.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace canonform::bench {

using Clock = std::chrono::steady_clock;

/// Seconds since t0.
inline double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Median of v (the upper one of an even count; 0 if empty).
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace canonform::bench
