// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/portable_math.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/vector4d.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace canonform::numerics {

namespace {

constexpr double kPi = 3.141592653589793;           // pi rounded to double
constexpr double kHalfPi = 1.5707963267948966;      // pi/2 rounded to double
constexpr double kQuarterPi = 0.7853981633974483;   // pi/4 rounded to double
constexpr double kTanPiOver8 = 0.4142135623730950;  // sqrt(2) - 1
constexpr double kLn2 = 0.69314718055994530942;

// 1/k! for k = 0..13 (k! is exact in double; one correctly rounded division each).
constexpr std::array<double, 14> inverse_factorials() {
    std::array<double, 14> inv{};
    double f = 1;
    for (int k = 0; k < 14; ++k) {
        if (k > 0) f *= k;
        inv[static_cast<size_t>(k)] = 1.0 / f;
    }
    return inv;
}
constexpr std::array<double, 14> kInverseFactorial = inverse_factorials();

// 2^n for an integer n in [-1022, 1023]: the double whose exponent field is n + 1023.
double power_of_two(double n) {
    const std::uint64_t bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(n) + 1023) << 52;
    double scale;
    std::memcpy(&scale, &bits, sizeof scale);
    return scale;
}

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

double portable_exp(double x) {
    if (std::isnan(x)) return x;
    if (x > 709.79) return HUGE_VAL;
    if (x < -745.2) return 0.0;
    constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
    const double n = std::floor(x / kLn2 + 0.5);
    const double r = (x - n * kLn2Hi) - n * kLn2Lo;
    double p = kInverseFactorial[13];
    for (int k = 12; k >= 0; --k) p = p * r + kInverseFactorial[static_cast<size_t>(k)];
    // times 2^n, exactly where the result is normal; in two steps at the ends of the range (n = 1024
    // near the overflow threshold, and subnormal results, which round once, in the last step).
    if (n > 1023) return p * power_of_two(n - 1) * 2.0;
    if (n < -1021) return p * power_of_two(n + 600) * power_of_two(-600);
    return p * power_of_two(n);
}

namespace {

// portable_exp of four values, one per lane, into out; false (nothing written) if one of them
// needs the scalar's special cases (NaN, beyond the range, a scale 2^n outside [-1021, 1023]).
bool exp_four(const double* xp, double* out) {
    const v4d x = load4d(xp);
    const v4l in_range = (x <= 709.79) & (x >= -745.2);  // false for NaN
    if (!(in_range[0] & in_range[1] & in_range[2] & in_range[3])) return false;
    constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
    const v4d t = x / kLn2 + 0.5;
    const v4d n = {std::floor(t[0]), std::floor(t[1]), std::floor(t[2]), std::floor(t[3])};
    const v4l normal = (n <= 1023.0) & (n >= -1021.0);
    if (!(normal[0] & normal[1] & normal[2] & normal[3])) return false;
    const v4d r = (x - n * kLn2Hi) - n * kLn2Lo;
    v4d p = v4d{} + kInverseFactorial[13];
    for (int k = 12; k >= 0; --k) p = p * r + kInverseFactorial[static_cast<size_t>(k)];
    const v4d scale = {power_of_two(n[0]), power_of_two(n[1]), power_of_two(n[2]), power_of_two(n[3])};
    store4d(out, p * scale);
    return true;
}

}  // namespace

CANONFORM_CLONES void portable_exp(const double* x, double* out, std::size_t count) {
    std::size_t k = 0;
    for (; k + 4 <= count; k += 4)
        if (!exp_four(x + k, out + k))
            for (std::size_t u = k; u < k + 4; ++u) out[u] = portable_exp(x[u]);
    for (; k < count; ++k) out[k] = portable_exp(x[k]);
}

double portable_exp2(double x) {
    return portable_exp(x * kLn2);
}

void portable_sincos(double a, double& sin_a, double& cos_a) {
    if (!(std::abs(a) <= 1e6)) {  // NaN, infinite, or beyond the exact reduction
        sin_a = cos_a = std::numeric_limits<double>::quiet_NaN();
        return;
    }
    constexpr double kHalfPiHi = 1.57079632673412561417e+00, kHalfPiLo = 6.07710050650619224932e-11;
    const double q = std::floor(a / kHalfPi + 0.5);
    const double r = (a - q * kHalfPiHi) - q * kHalfPiLo;
    const double r2 = r * r;
    double ps = 0, pc = 0, ts = r, tc = 1;
    for (int k = 1; k <= 9; ++k) {  // terms r^(2k-1) / (2k-1)! and r^(2k-2) / (2k-2)!
        ps += ts;
        pc += tc;
        ts = -ts * r2 / double((2 * k) * (2 * k + 1));
        tc = -tc * r2 / double((2 * k - 1) * (2 * k));
    }
    const long quadrant = static_cast<long>(q) & 3;
    sin_a = quadrant == 0 ? ps : quadrant == 1 ? pc : quadrant == 2 ? -ps : -pc;
    cos_a = quadrant == 0 ? pc : quadrant == 1 ? -ps : quadrant == 2 ? -pc : ps;
}

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
        r = num > kTanPiOver8 * den ? kQuarterPi + atan_reduced((num - den) / (num + den))
                                    : atan_reduced(num / den);
        if (steep) r = kHalfPi - r;
    }
    if (std::signbit(x)) r = kPi - r;
    return std::signbit(y) ? -r : r;
}

namespace {

inline v4d select(v4l mask, v4d a, v4d b) {  // a where mask, else b (bit for bit)
    return reinterpret_cast<v4d>((reinterpret_cast<v4l>(a) & mask) | (reinterpret_cast<v4l>(b) & ~mask));
}
inline bool any(v4l m) {
    return (m[0] | m[1] | m[2] | m[3]) != 0;
}

// atan_reduced() of four values: each lane's terms as the scalar's, its sum frozen when the scalar
// loop would stop.
inline v4d atan_reduced4(v4d s) {
    const v4d q = 1.0 / (1.0 + s * s);
    const v4d z = s * s * q;
    v4d term = s * q, sum = term;
    v4l active = z == z;  // every lane
    for (int n = 1; n < 40 && any(active); ++n) {
        term *= z * (2.0 * n) / (2.0 * n + 1.0);
        const v4d next = sum + term;
        const v4l moved = active & (next != sum);
        sum = select(moved, next, sum);
        active = moved;
    }
    return sum;
}

// Four angles; false (nothing written) when a lane needs one of the scalar's special cases.
inline bool atan2_four(const double* yp, const double* xp, double* out) {
    const v4d y = load4d(yp), x = load4d(xp);
    const v4l magnitude = {INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX};
    const v4d ax = reinterpret_cast<v4d>(reinterpret_cast<v4l>(x) & magnitude);
    const v4d ay = reinterpret_cast<v4d>(reinterpret_cast<v4l>(y) & magnitude);
    const double inf = std::numeric_limits<double>::infinity();
    // NaN (not equal to itself), infinite, or y = 0: the scalar's own paths.
    if (any((ax != ax) | (ay != ay) | (ax == inf) | (ay == inf) | (ay == 0.0))) return false;
    const v4l steep = ay > ax;
    const v4d num = select(steep, ax, ay), den = select(steep, ay, ax);  // num / den in [0, 1]
    const v4l far = num > kTanPiOver8 * den;
    v4d r = atan_reduced4(select(far, (num - den) / (num + den), num / den));
    r = select(far, kQuarterPi + r, r);
    r = select(steep, kHalfPi - r, r);
    const v4l sign_x = reinterpret_cast<v4l>(x) < 0, sign_y = reinterpret_cast<v4l>(y) < 0;
    r = select(sign_x, kPi - r, r);
    r = select(sign_y, -r, r);
    store4d(out, r);
    return true;
}

}  // namespace

CANONFORM_CLONES void portable_atan2(const double* y, const double* x, double* out, std::size_t count) {
    std::size_t k = 0;
    for (; k + 4 <= count; k += 4)
        if (!atan2_four(y + k, x + k, out + k))
            for (std::size_t u = k; u < k + 4; ++u) out[u] = portable_atan2(y[u], x[u]);
    for (; k < count; ++k) out[k] = portable_atan2(y[k], x[k]);
}

double portable_log(double x) {
    if (std::isnan(x) || x < 0) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0) return -HUGE_VAL;
    if (std::isinf(x)) return x;
    int e = 0;
    double m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1): exact, subnormal x too
    if (m < 0.70710678118654752) {
        m *= 2;  // exact
        --e;
    }
    // ln m = ln(1 + f) = f - (f^2/2 - s (f^2/2 + R)), s = f / (2 + f), R = 2 s^2/3 + 2 s^4/5 + ...:
    // f is exact (Sterbenz), so the rounding errors fall on the small correction only.
    const double f = m - 1, s = f / (2 + f), z = s * s, hfsq = 0.5 * f * f;
    double term = z, r = 0;
    for (int k = 3; k < 80; k += 2) {
        const double next = r + 2 * term / k;
        if (next == r) break;
        r = next;
        term *= z;
    }
    constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
    return e * kLn2Hi - ((hfsq - (s * (hfsq + r) + e * kLn2Lo)) - f);
}

double StandardNormalDraws::operator()(std::mt19937_64& rng) {
    if (saved_) {
        saved_ = false;
        return next_;
    }
    const auto uniform = [&rng] { return 2.0 * (static_cast<double>(rng() >> 11) * 0x1.0p-53) - 1.0; };
    double u, v, r2;
    do {
        u = uniform();
        v = uniform();
        r2 = u * u + v * v;
    } while (r2 > 1.0 || r2 == 0.0);
    const double f = std::sqrt(-2.0 * portable_log(r2) / r2);
    next_ = u * f;
    saved_ = true;
    return v * f;
}

}  // namespace canonform::numerics
