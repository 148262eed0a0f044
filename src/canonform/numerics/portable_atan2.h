// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: an arctangent whose result is the same on every x86-64 CPU.
//
// Why: glibc's libm picks its implementation of atan2 (and of sin, cos, atan, acos, exp, log, pow)
// at run time; on CPUs with FMA and AVX2 its FMA variant differs from the SSE2 one in the last bit
// for about 1 argument in 3000 (measured on glibc 2.36, Debian bookworm). One such bit in a
// vertex's angle sum changed the canonical form of a 5,000-vertex TOSCA mesh by 5e-10 through
// SMACOF. This function uses only +, -, *, / and comparisons, which IEEE 754 rounds identically
// on every x86-64 CPU, in an order fixed at compile time.
//
// Method (standard identities, no table): with t = min(|x|, |y|) / max(|x|, |y|) in [0, 1],
// atan t = pi/4 + atan((t - 1) / (t + 1)) when t > tan(pi/8), which leaves an argument s with
// |s| <= tan(pi/8) = 0.4142; there Euler's series
//     atan s = sum_{n>=0} (2^(2n) (n!)^2 / (2n+1)!) s^(2n+1) / (1 + s^2)^(n+1)
// has terms of one sign that shrink by the factor (2n / (2n+1)) s^2 / (1 + s^2) <= 0.147, so about
// 20 terms reach double precision. Then the octant: pi/2 - r when |y| > |x|, pi - r when x < 0,
// the sign of y. Accuracy: within 4.5e-16 absolute and 1.1e-15 relative (5 units in the last
// place) of libm's atan2 (tested); special values: atan2(+-0, x) is +-0 for x >= +0 and +-pi for x <= -0 as in C; a NaN
// argument gives NaN.
#pragma once

namespace canonform::numerics {

/// The angle of the point (x, y) in (-pi, pi], like std::atan2, but the same bits on every CPU.
double portable_atan2(double y, double x);

}  // namespace canonform::numerics
