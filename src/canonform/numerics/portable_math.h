// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: elementary functions whose results are the same bits on every x86-64 CPU.
//
// Why: glibc's libm picks its implementation of exp, log, pow, sin, cos, atan and atan2 at run
// time; on CPUs with FMA and AVX2 its FMA variants differ from the SSE2 ones in the last bit for
// about 1 argument in 3000 (measured on glibc 2.36, Debian bookworm). One such bit in a vertex's
// angle sum changed the canonical form of a 5,000-vertex TOSCA mesh by 5e-10 through SMACOF, and
// one in a Gaussian tap changes a SIFT descriptor. The functions here use only +, -, *, /, sqrt,
// comparisons, floor and exact scalings by powers of two, which IEEE 754 rounds identically on
// every x86-64 CPU, in an order fixed at compile time (this file's source is compiled without FMA
// contraction: src/CMakeLists.txt).
//
// Methods (standard identities and series, no table; accuracies measured against glibc's libm by
// tests/test_portable_math.cpp):
// - portable_exp(x): x = n ln2 + r, |r| <= ln2 / 2, with ln2 in two parts (Cody and Waite's
//   reduction; the first part has trailing zero bits so that n times it is exact), e^r by its Taylor
//   series to r^13 by Horner's rule (truncation below 1e-17 relative), times 2^n exactly.
//   Accuracy: within 2.5e-16 relative of libm's exp (about 1 unit in the last place) for every x
//   that gives a normal double (x in [-708, 709.78]); below that the result is gradual underflow
//   (relative accuracy lost in the subnormal range) and 0 under -745.2; +inf above 709.79.
//   e^0 = 1 exactly; NaN gives NaN.
// - portable_exp2(x) = portable_exp(x ln2): within 2.5e-16 relative plus the rounding of x ln2,
//   |x| 1.1e-16 relative (7e-16 for |x| <= 6, the SIFT's use).
// - portable_sincos(a): a = q pi/2 + r, |r| <= pi/4, with pi/2 in two parts (Cody and Waite), the
//   Taylor series of sin r to r^17 and of cos r to r^16, then the quadrant of q. Accuracy: within
//   3.4e-16 absolute of libm's sin and cos for |a| <= 1e4 (the reduction's error grows with |q|:
//   within 1e-13 for |a| <= 1e6). Beyond 1e6, where q pi/2's first part is no longer exact, and for
//   a non-finite a: NaN for both.
// - portable_atan2(y, x): with t = min(|x|, |y|) / max(|x|, |y|) in [0, 1], atan t = pi/4 +
//   atan((t - 1) / (t + 1)) when t > tan(pi/8), which leaves an argument s with |s| <= tan(pi/8) =
//   0.4142; there Euler's series
//       atan s = sum_{n>=0} (2^(2n) (n!)^2 / (2n+1)!) s^(2n+1) / (1 + s^2)^(n+1)
//   has terms of one sign that shrink by the factor (2n / (2n+1)) s^2 / (1 + s^2) <= 0.147, so about
//   20 terms reach double precision. Then the octant: pi/2 - r when |y| > |x|, pi - r when x < 0,
//   the sign of y. Accuracy: within 4.5e-16 absolute and 1.2e-15 relative (5 units in the last
//   place) of libm's atan2; special values as in C: atan2(+-0, x) is +-0 for x >= +0 and +-pi for
//   x <= -0, infinities give the octant's angle, a NaN argument gives NaN.
// - portable_log(x): x = m 2^e with m in [sqrt(1/2), sqrt(2)) (frexp, exact), ln x = e ln 2 + ln m
//   with ln 2 in two parts (the first exact times e). With f = m - 1 (exact) and s = f / (2 + f),
//   ln m = 2 atanh s = 2s + s R, R = 2 s^2/3 + 2 s^4/5 + ... (|s| <= 0.1716: the terms shrink by
//   s^2 <= 0.0295), and 2s = f - s f, so ln m = f - (f^2/2 - s (f^2/2 + R)): the leading term f is
//   exact and the roundings fall on the correction (the arrangement of fdlibm's e_log.c, written
//   here from the identity). Accuracy: within 1 unit in the last place of libm's log (the test
//   draws 200,000 arguments); log 0 = -inf, log of a negative number or NaN is NaN, log inf = inf.
// - StandardNormalDraws: standard normal random numbers from a std::mt19937_64, by the polar method
//   of G. Marsaglia and T. A. Bray, "A convenient method for generating normal variables", SIAM
//   Review 6(3), 1964: (u, v) uniform in the unit disc (by rejection), r2 = u^2 + v^2, then
//   u sqrt(-2 ln r2 / r2) and v sqrt(-2 ln r2 / r2) are two independent draws (the second is kept
//   for the next call, as std::normal_distribution does); ln by portable_log, the square root
//   correctly rounded by IEEE 754. Departure from std::normal_distribution (libstdc++ uses the same
//   method): its std::log differs between C libraries (glibc, MinGW's on Windows) and glibc's CPU
//   variants, and its uniform numbers come from std::generate_canonical; here u and v are the top
//   53 bits of one output each. So the numbers differ from std::normal_distribution's, not their law.
// - approximate_angle_0_to_2pi(y, x): a float angle for the SIFT's gradient directions, where a
//   hundred-thousandth of a radian is far below the histogram bins' width (10 degrees): atan a for
//   a = min / max of |x|, |y| in [0, 1] by an odd polynomial of degree 9 fitted by us (least squares
//   with Lawson's weights) to within 1.2e-5 rad, then the octant, in float arithmetic. Range
//   [0, 2 pi] (2 pi itself only when the angle lies within float rounding of it, below); (0, 0)
//   gives 0. A 4-lane form for the SIFT windows is in views/sift_simd.h (the same operations per
//   lane, so the same bits).
#pragma once

#include <cstddef>
#include <random>

namespace canonform::numerics {

/// e^x, the same bits on every CPU (see above for the accuracy).
double portable_exp(double x);
/// portable_exp(x[k]) into out[k] for k < count, the same bits, four at a time in vector
/// instructions (one lane per value, each lane the scalar's operations).
void portable_exp(const double* x, double* out, std::size_t count);

/// 2^x, the same bits on every CPU.
double portable_exp2(double x);

/// sin a and cos a (radians), the same bits on every CPU; NaN for |a| > 1e6 (see above).
void portable_sincos(double a, double& sin_a, double& cos_a);

/// The angle of the point (x, y) in (-pi, pi], like std::atan2, but the same bits on every CPU.
double portable_atan2(double y, double x);
/// portable_atan2(y[k], x[k]) into out[k] for k < count, the same bits, several at a time in vector
/// instructions (one lane per angle, each lane the scalar's operations).
void portable_atan2(const double* y, const double* x, double* out, std::size_t count);

/// The natural logarithm of x, within 1 unit in the last place of std::log, the same bits on every
/// CPU and with every C library (see above for the special values).
double portable_log(double x);

/// Standard normal random numbers (mean 0, variance 1) from a std::mt19937_64, the same for a seed
/// on every CPU and with every C library (the polar method, see above): a replacement for
/// std::normal_distribution<double> in results.
class StandardNormalDraws {
public:
    /// The next draw.
    double operator()(std::mt19937_64& rng);

private:
    bool saved_ = false;  ///< the second draw of the last pair is waiting in next_
    double next_ = 0;
};

/// The coefficients of approximate_angle_0_to_2pi's polynomial a (c1 + a^2 (c3 + a^2 (c5 + ...)))
/// and its float constants, shared with its vector form.
struct ApproximateAngle {
    static constexpr float c1 = 0.999866332f, c3 = -0.330304798f, c5 = 0.180159301f, c7 = -0.0851563296f,
                           c9 = 0.0208450956f;
    static constexpr float half_pi = 1.57079637f, pi = 3.14159274f, two_pi = 6.28318548f;
};

/// The angle of (x, y) in [0, 2 pi] radians, counted from +x towards +y, within 1.2e-5 rad (see
/// above); 0 for (0, 0). Float arithmetic, inline: the same bits on every CPU when compiled
/// without FMA contraction (the views area is).
inline float approximate_angle_0_to_2pi(float y, float x) {
    using A = ApproximateAngle;
    const float ax = x < 0.f ? -x : x, ay = y < 0.f ? -y : y;
    const float big = ax < ay ? ay : ax, small = ay < ax ? ay : ax;
    if (!(big > 0.f)) return 0.f;
    const float a = small / big, a2 = a * a;
    float t = a * (A::c1 + a2 * (A::c3 + a2 * (A::c5 + a2 * (A::c7 + a2 * A::c9))));
    if (ay > ax) t = A::half_pi - t;
    if (x < 0.f) t = A::pi - t;
    if (y < 0.f) t = A::two_pi - t;
    return t;
}

}  // namespace canonform::numerics
