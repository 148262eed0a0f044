// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: four doubles in one vector (GCC and Clang's vector extensions) for loops that keep each
// lane's IEEE operations those of the scalar code they replace: one AVX instruction in an AVX2
// clone (common/cpu_clones.h), two SSE2 ones in the baseline, the same bits in both.
//
// A function that passes these by value must be inlined into its caller, never called across
// clones (their calling conventions for 32-byte vectors differ): GCC's -Wpsabi note says so, and
// is silenced where this header is included.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace canonform {

typedef double v4d __attribute__((vector_size(32)));
/// Lane masks of v4d comparisons (all bits set where true).
typedef std::int64_t v4l __attribute__((vector_size(32)));

inline v4d load4d(const double* p) {
    v4d v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

inline void store4d(double* p, const v4d& v) {
    std::memcpy(p, &v, sizeof v);
}

}  // namespace canonform
