// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: wall seconds since a point of the steady clock, the stage times that runs report.
#pragma once

#include <chrono>

namespace canonform {

using SteadyClock = std::chrono::steady_clock;

/// Seconds from t0 to now on the steady clock.
inline double seconds_since(SteadyClock::time_point t0) {
    return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace canonform
