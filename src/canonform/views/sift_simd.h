// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the SIFT extractor's vector helpers (private to the views area; sift_features.h says
// why the results are the same bits on every CPU).
//
// 4-, 8- and 16-float vectors of the GCC/Clang vector extension. 4 lanes are SSE2 on x86-64 (in
// every x86-64 CPU); 8 lanes are one AVX2 instruction in a function cloned for AVX2
// (CANONFORM_CLONES, common/cpu_clones.h: the clone is picked at run time) and a pair of SSE2
// instructions elsewhere; 16 lanes (the blur, CANONFORM_CLONES_AVX512) one AVX-512 instruction in
// its x86-64-v4 clone. Each lane does exactly what the scalar code of the same loop does, in the
// same order (no FMA: the views area is compiled with -ffp-contract=off, and AVX2 does not imply
// FMA), so the choice changes no bit.
#pragma once

#include "canonform/common/cpu_clones.h"
#include "canonform/numerics/portable_math.h"

#include <cmath>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

// The 8-float helpers are inlined: no call passes a v8f between code built for different targets.
// (clang, which never makes the clones, says so too from -O2, for the helpers' signatures.)
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

// Helpers that take or return 8-float vectors are always inlined into their (cloned) callers.
#if defined(__GNUC__)
#define CANONFORM_SIMD_INLINE inline __attribute__((always_inline))
#else
#define CANONFORM_SIMD_INLINE inline
#endif

namespace canonform::views {
namespace sift {

typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));
typedef float v8f __attribute__((vector_size(32)));
typedef int v8i __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));

inline v4f load4(const float* p) {
    v4f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store4(float* p, v4f v) {
    std::memcpy(p, &v, sizeof v);
}
inline v4f splat4(float x) {
    return v4f{x, x, x, x};
}
// Bit q set when lane q of the mask is set.
inline unsigned mask4(v4i m) {
#if defined(__SSE__)
    return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
    return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
#endif
}

inline v4f select4(v4i mask, v4f a, v4f b) {
    return mask ? a : b;
}
inline v4f sqrt4(v4f x) {
#if defined(__SSE__)
    return reinterpret_cast<v4f>(_mm_sqrt_ps(reinterpret_cast<__m128>(x)));  // IEEE sqrt, as std::sqrt
#else
    return v4f{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

inline v8f load8(const float* p) {
    v8f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store8(float* p, const v8f& v) {
    std::memcpy(p, &v, sizeof v);
}
inline v8f splat8(float x) {
    return v8f{x, x, x, x, x, x, x, x};
}
inline v8i splat8i(int x) {
    return v8i{x, x, x, x, x, x, x, x};
}
inline v16f load16(const float* p) {
    v16f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store16(float* p, const v16f& v) {
    std::memcpy(p, &v, sizeof v);
}
inline v16f splat16(float x) {
    return v16f{} + x;
}
inline unsigned mask8(v8i m) {
    v4i lo, hi;
    std::memcpy(&lo, &m, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&m) + sizeof lo, sizeof hi);
    return mask4(lo) | (mask4(hi) << 4);
}

// base[0], base[p], ..., base[7p], lanes past `last` (the last lane wanted) reading lane last's
// value instead (no read beyond it when p > 1; with p = 1, 8 consecutive floats).
CANONFORM_SIMD_INLINE v8f load8s(const float* base, int p, int last) {
    if (p == 1) return load8(base);
    v8f v;
    for (int l = 0; l < 8; ++l) v[l] = base[(l < last ? l : last) * p];
    return v;
}
// floor(x) per lane as integers, for |x| < 2^31: the truncation, one less where it rounded up.
CANONFORM_SIMD_INLINE v8i floor8i(v8f x) {
    const v8i t = __builtin_convertvector(x, v8i);
    return t + (__builtin_convertvector(t, v8f) > x);
}
CANONFORM_SIMD_INLINE v8f sqrt8(v8f x) {
    v4f lo, hi;
    std::memcpy(&lo, &x, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&x) + sizeof lo, sizeof hi);
    lo = sqrt4(lo);
    hi = sqrt4(hi);
    std::memcpy(&x, &lo, sizeof lo);
    std::memcpy(reinterpret_cast<char*>(&x) + sizeof lo, &hi, sizeof hi);
    return x;
}

// The central-difference gradients (gx along the row, gy down) of the eight samples x, x + p, ...,
// x + 7p of row `mid` (rows `up` and `down` around it; lanes past `last` as load8s reads them), and
// their magnitudes.
CANONFORM_SIMD_INLINE void gradients8(const float* up, const float* mid, const float* down, int x, int p,
                                      int last, v8f& gx, v8f& gy, v8f& m) {
    gx = load8s(mid + x + 1, p, last) - load8s(mid + x - 1, p, last);
    gy = load8s(down + x, p, last) - load8s(up + x, p, last);
    m = sqrt8(gx * gx + gy * gy);
}

/// numerics::approximate_angle_0_to_2pi for the lanes of V (v4f or v8f) whose (x, y) are not both
/// 0: the same operations per lane, so the same bits.
template <typename V>
CANONFORM_SIMD_INLINE V approximate_angle_0_to_2pi_lanes(V y, V x) {
    using A = numerics::ApproximateAngle;
    const V zero = V{} + 0.f;
    const V ax = x < zero ? -x : x, ay = y < zero ? -y : y;
    const V big = ax < ay ? ay : ax, small = ay < ax ? ay : ax;  // std::max's and std::min's choices
    const V a = small / big, a2 = a * a;
    V t = a * ((V{} + A::c1) +
               a2 * ((V{} + A::c3) + a2 * ((V{} + A::c5) + a2 * ((V{} + A::c7) + a2 * (V{} + A::c9)))));
    t = ay > ax ? (V{} + A::half_pi) - t : t;
    t = x < zero ? (V{} + A::pi) - t : t;
    t = y < zero ? (V{} + A::two_pi) - t : t;
    return t;
}

}  // namespace sift
}  // namespace canonform::views
