// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/portable_atan2.h"

#include <cmath>
#include <limits>

namespace canonform::numerics {

namespace {

constexpr double kPi = 3.141592653589793;           // pi rounded to double
constexpr double kHalfPi = 1.5707963267948966;       // pi/2 rounded to double
constexpr double kQuarterPi = 0.7853981633974483;    // pi/4 rounded to double
constexpr double kTanPiOver8 = 0.4142135623730950;  // sqrt(2) - 1

// atan s for |s| <= tan(pi/8) by Euler's series (terms of the sign of s, shrinking by <= 0.147).
double atan_reduced(double s) {
    const double q = 1.0 / (1.0 + s * s);
    const double z = s * s * q;
    double term = s * q, sum = term;
    for (int n = 1; n < 40; ++n) {
        term *= z * (2.0 * n) / (2.0 * n + 1.0);
        const double next = sum + term;
        if (next == sum) break;
        sum = next;
    }
    return sum;
}

}  // namespace

double portable_atan2(double y, double x) {
    if (std::isnan(x) || std::isnan(y)) return std::numeric_limits<double>::quiet_NaN();
    const double ax = std::abs(x), ay = std::abs(y);
    double r;
    if (ay == 0.0) {
        r = 0.0;
    } else if (std::isinf(ax) || std::isinf(ay)) {
        r = std::isinf(ax) ? (std::isinf(ay) ? kQuarterPi : 0.0) : kHalfPi;
    } else {
        const bool steep = ay > ax;
        const double num = steep ? ax : ay, den = steep ? ay : ax;  // num / den in [0, 1]
        r = num > kTanPiOver8 * den ? kQuarterPi + atan_reduced((num - den) / (num + den)) : atan_reduced(num / den);
        if (steep) r = kHalfPi - r;
    }
    if (std::signbit(x)) r = kPi - r;
    return std::signbit(y) ? -r : r;
}

}  // namespace canonform::numerics
