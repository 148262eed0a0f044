// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: error types shared by the core.
//
// InputError     - the input mesh cannot be processed (names the problem: no faces, NaN, ...).
// NumericalError - a factorisation or solve failed or produced a residual above tolerance.
// Both derive from std::runtime_error; what() is a complete sentence meant for the user.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace canonform {

/// The input cannot be processed; what() names the problem and, where possible, the remedy.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A numerical step failed (factorisation, non-finite values, residual above tolerance).
class NumericalError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Progress report: fraction in [0, 1] and a short stage label. Return false to cancel
/// (the algorithm then throws canonform::Cancelled).
using ProgressFn = std::function<bool(double fraction, const char* stage)>;

/// Thrown when a ProgressFn asked to stop.
class Cancelled : public std::runtime_error {
public:
    Cancelled() : std::runtime_error("cancelled by the user") {}
};

/// Calls `progress` (if set) and throws Cancelled when it returns false.
inline void report_progress(const ProgressFn& progress, double fraction, const char* stage) {
    if (progress && !progress(fraction, stage)) throw Cancelled();
}

}  // namespace canonform
