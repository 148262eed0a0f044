// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/sift_features.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <cstdlib>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace canonform::views {

// ---- backends -------------------------------------------------------------------------------------

const std::vector<std::string>& sift_backend_names() {
    static const std::vector<std::string> names = {"canonform", "opencv"};
    return names;
}

const std::vector<std::string>& builtin_sift_backend_names() {
    static const std::vector<std::string> names = {"canonform"};
    return names;
}

SiftBackend parse_sift_backend(const std::string& name) {
    const auto& names = sift_backend_names();
    std::string choices;
    for (size_t k = 0; k < names.size(); ++k) {
        if (names[k] == name) return static_cast<SiftBackend>(k);
        choices += (k ? ", " : "") + names[k];
    }
    for (const char* removed : {"opencv-half", "opencv-fast", "opencv-octave0", "opencv-octave0-fine", "vlfeat"})
        if (name == removed)
            throw InputError("SIFT: the backend '" + name + "' was removed (issue 23: its code was not written in this project, " +
                             "or it was measured no better than the others); 'canonform' replaces it (" +
                             choices + ").");
    throw InputError("SIFT: unknown backend '" + name + "' (" + choices + ").");
}

std::string sift_backend_name(SiftBackend backend) { return sift_backend_names().at(static_cast<size_t>(backend)); }

namespace {

std::array<std::atomic<SiftExtractor>, 2> g_extractors{};

}  // namespace

void register_sift_extractor(SiftBackend backend, SiftExtractor extractor) {
    g_extractors.at(static_cast<size_t>(backend)).store(extractor);
}

bool sift_backend_available(SiftBackend backend) {
    return backend == SiftBackend::Canonform || g_extractors.at(static_cast<size_t>(backend)).load() != nullptr;
}

namespace {

// ---- elementary functions of our own (bit-identical on every CPU, see the header) ----------------

constexpr double kPi = 3.14159265358979323846;
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

// e^x for x <= 0 (and moderate x > 0): x = n ln2 + r with |r| <= ln2 / 2 (ln2 in two parts, the
// first with trailing zero bits so that n * kLn2Hi is exact), e^r by its Taylor series to r^13
// (remainder below 1e-17 relative), times 2^n exactly.
double exp_det(double x) {
    if (x < -700.0) return 0.0;
    if (x > 700.0) return HUGE_VAL;
    constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
    const double n = std::floor(x / kLn2 + 0.5);
    const double r = (x - n * kLn2Hi) - n * kLn2Lo;
    double p = kInverseFactorial[13];
    for (int k = 12; k >= 0; --k) p = p * r + kInverseFactorial[static_cast<size_t>(k)];
    // times 2^n (n >= -1011 here): the double whose exponent field is n + 1023, exactly.
    const std::uint64_t bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(n) + 1023) << 52;
    double scale;
    std::memcpy(&scale, &bits, sizeof scale);
    return p * scale;
}

// 2^x.
double exp2_det(double x) { return exp_det(x * kLn2); }

// sin and cos of a (radians, any finite value of moderate size): a = q pi/2 + r, |r| <= pi/4
// (pi/2 in two parts), Taylor series of sin r to r^17 and cos r to r^16, then the quadrant.
void sincos_det(double a, double& s, double& c) {
    constexpr double kHalfPiHi = 1.57079632673412561417e+00, kHalfPiLo = 6.07710050650619224932e-11;
    const double q = std::floor(a / (kPi / 2) + 0.5);
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
    s = quadrant == 0 ? ps : quadrant == 1 ? pc : quadrant == 2 ? -ps : -pc;
    c = quadrant == 0 ? pc : quadrant == 1 ? -ps : quadrant == 2 ? -pc : ps;
}

// Four floats at once (GCC/Clang vector extension; SSE2 on x86-64, in every x86-64 CPU). Each lane
// does exactly what the scalar code of the same loop does, in the same order.
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));
inline v4f load4(const float* p) {
    v4f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store4(float* p, v4f v) { std::memcpy(p, &v, sizeof v); }
inline v4f splat4(float x) { return v4f{x, x, x, x}; }
inline v4i splat4i(int x) { return v4i{x, x, x, x}; }
// base[0], base[p], base[2p], base[3p].
inline v4f load4s(const float* base, int p) { return p == 1 ? load4(base) : v4f{base[0], base[p], base[2 * p], base[3 * p]}; }
// The first value >= v with (value - origin) a multiple of p (p > 0).
inline int align_up(int v, int origin, int p) {
    const int d = v - origin;
    return origin + (d >= 0 ? (d + p - 1) / p : -((-d) / p)) * p;
}
// Bit q set when lane q of the mask is set.
inline unsigned mask4(v4i m) {
#if defined(__SSE__)
    return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
    return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
#endif
}

inline v4f select4(v4i mask, v4f a, v4f b) { return mask ? a : b; }
inline v4f max4(v4f a, v4f b) { return a < b ? b : a; }  // std::max's choice, per lane
inline v4f min4(v4f a, v4f b) { return b < a ? b : a; }  // std::min's choice, per lane
inline v4f sqrt4(v4f x) {
#if defined(__SSE__)
    return reinterpret_cast<v4f>(_mm_sqrt_ps(reinterpret_cast<__m128>(x)));  // IEEE sqrt, as std::sqrt
#else
    return v4f{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

// atan2(y, x) in radians, [0, 2 pi): atan(a) for a = min/max of |x|, |y| in [0, 1] by an odd
// polynomial of degree 9 fitted (by us, least squares with Lawson weights) to within 1.2e-5 rad,
// then the octant. atan2(0, 0) = 0. The scalar and the four-lane form compute the same.
constexpr float kAtan1 = 0.999866332f, kAtan3 = -0.330304798f, kAtan5 = 0.180159301f, kAtan7 = -0.0851563296f,
                kAtan9 = 0.0208450956f;
constexpr float kHalfPiF = 1.57079637f, kPiF = 3.14159274f, kTwoPiF = 6.28318548f;
inline float atan2_det(float y, float x) {
    const float ax = std::abs(x), ay = std::abs(y);
    const float big = std::max(ax, ay), small = std::min(ax, ay);
    if (!(big > 0.f)) return 0.f;
    const float a = small / big, a2 = a * a;
    float t = a * (kAtan1 + a2 * (kAtan3 + a2 * (kAtan5 + a2 * (kAtan7 + a2 * kAtan9))));
    if (ay > ax) t = kHalfPiF - t;
    if (x < 0.f) t = kPiF - t;
    if (y < 0.f) t = kTwoPiF - t;
    return t;
}
// The same for four lanes whose (x, y) are not both 0.
inline v4f atan2_det4(v4f y, v4f x) {
    const v4f zero = splat4(0.f);
    const v4f ax = select4(x < zero, -x, x), ay = select4(y < zero, -y, y);
    const v4f big = max4(ax, ay), small = min4(ax, ay);
    const v4f a = small / big, a2 = a * a;
    v4f t = a * (splat4(kAtan1) + a2 * (splat4(kAtan3) + a2 * (splat4(kAtan5) + a2 * (splat4(kAtan7) + a2 * splat4(kAtan9)))));
    t = select4(ay > ax, splat4(kHalfPiF) - t, t);
    t = select4(x < zero, splat4(kPiF) - t, t);
    t = select4(y < zero, splat4(kTwoPiF) - t, t);
    return t;
}

// ---- images ---------------------------------------------------------------------------------------

// A half-open rectangle of pixels [x0, x1) x [y0, y1) in an octave's integer coordinates (pixel X
// of octave o is view position X 2^o).
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    Rect grown(int m) const { return {x0 - m, y0 - m, x1 + m, y1 + m}; }
    Rect meet(const Rect& o) const {
        return {std::max(x0, o.x0), std::max(y0, o.y0), std::min(x1, o.x1), std::min(y1, o.y1)};
    }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

// One image of an octave: values over `support`, 0 outside it (never read there); stored in a
// buffer covering `frame` (row y, column x at data[(y - frame.y0) * stride + x - frame.x0]).
struct Plane {
    float* data = nullptr;
    Rect frame, support;
    int stride = 0;
    float* row(int y) const { return data + static_cast<std::ptrdiff_t>(y - frame.y0) * stride - frame.x0; }
    float at(int x, int y) const { return row(y)[x]; }
};

// A symmetric Gaussian kernel truncated at 4 sigma: taps[0..radius], normalised so that the
// whole kernel sums to 1 (in double, then rounded to float).
struct Kernel {
    int radius = 0;
    std::vector<float> taps;
};

int support_radius(double sigma) { return std::max(1, static_cast<int>(std::ceil(4.0 * sigma))); }

Kernel gaussian_kernel(double sigma) {
    Kernel k;
    k.radius = support_radius(sigma);
    std::vector<double> w(static_cast<size_t>(k.radius) + 1);
    double sum = 0;
    for (int j = 0; j <= k.radius; ++j) {
        w[static_cast<size_t>(j)] = exp_det(-double(j) * double(j) / (2.0 * sigma * sigma));
        sum += (j == 0 ? 1.0 : 2.0) * w[static_cast<size_t>(j)];
    }
    for (double v : w) k.taps.push_back(static_cast<float>(v / sum));
    return k;
}

// Scratch memory of an extraction, kept per thread from one view to the next (a view's planes are a
// few hundred kilobytes each).
struct Workspace {
    std::vector<float> line;
    // Planes in two banks (octave o uses bank o % 2, so octave o - 1's planes stay readable).
    std::vector<std::unique_ptr<float[]>> planes[2];
    std::vector<size_t> plane_sizes[2];
    float* plane(int bank, int slot, size_t n) {
        auto& p = planes[bank];
        auto& z = plane_sizes[bank];
        if (p.size() <= static_cast<size_t>(slot)) {
            p.resize(static_cast<size_t>(slot) + 1);
            z.resize(static_cast<size_t>(slot) + 1, 0);
        }
        if (z[static_cast<size_t>(slot)] < n) {
            p[static_cast<size_t>(slot)].reset(new float[n]);
            z[static_cast<size_t>(slot)] = n;
        }
        return p[static_cast<size_t>(slot)].get();
    }
    std::unique_ptr<float[]> temp;
    size_t temp_size = 0;
    float* temp_for(size_t n) {
        if (n > temp_size) {
            temp.reset(new float[n]);
            temp_size = n;
        }
        return temp.get();
    }
};

// The two passes of the blur below, in blocks of 32 floats as 8-float vectors: on a CPU with AVX2 they
// run as 8-lane instructions (a clone of the function picked at run time), elsewhere as pairs of
// 4-lane SSE2 ones. Either way every lane does the same IEEE operations in the same order (no FMA:
// -ffp-contract=off, and AVX2 does not imply it), so the results are the same bits on every CPU.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"  // (the 8-float helpers are inlined: no call passes a v8f)
#endif
typedef float v8f __attribute__((vector_size(32)));
inline v8f load8(const float* p) {
    v8f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store8(float* p, v8f v) { std::memcpy(p, &v, sizeof v); }
inline v8f splat8(float x) { return v8f{x, x, x, x, x, x, x, x}; }

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define CANONFORM_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CANONFORM_SIMD_CLONES
#endif

// o[i] = k0 c[i] + k1 (c[i-1] + c[i+1]) + ... + kR (c[i-R] + c[i+R]) for i in [0, n), summed in
// that order (c must be readable at [-R, n + R)).
CANONFORM_SIMD_CLONES void convolve_line(const float* c, float* o, int n, const float* taps, int R) {
    int i = 0;
    for (; i + 32 <= n; i += 32) {
        const v8f k0 = splat8(taps[0]);
        v8f a0 = k0 * load8(c + i), a1 = k0 * load8(c + i + 8), a2 = k0 * load8(c + i + 16), a3 = k0 * load8(c + i + 24);
        for (int j = 1; j <= R; ++j) {
            const v8f kj = splat8(taps[j]);
            a0 += kj * (load8(c + i - j) + load8(c + i + j));
            a1 += kj * (load8(c + i + 8 - j) + load8(c + i + 8 + j));
            a2 += kj * (load8(c + i + 16 - j) + load8(c + i + 16 + j));
            a3 += kj * (load8(c + i + 24 - j) + load8(c + i + 24 + j));
        }
        store8(o + i, a0);
        store8(o + i + 8, a1);
        store8(o + i + 16, a2);
        store8(o + i + 24, a3);
    }
    for (; i + 8 <= n; i += 8) {
        v8f a = splat8(taps[0]) * load8(c + i);
        for (int j = 1; j <= R; ++j) a += splat8(taps[j]) * (load8(c + i - j) + load8(c + i + j));
        store8(o + i, a);
    }
    for (; i < n; ++i) {
        float a = taps[0] * c[i];
        for (int j = 1; j <= R; ++j) a += taps[j] * (c[i - j] + c[i + j]);
        o[i] = a;
    }
}

// o[i] = k0 r0[i] + k1 (m1[i] + p1[i]) + ... over rows r0, m_j = row -j, p_j = row +j, where a
// null row is 0 and its terms are left out (adding 0 changes no sum).
CANONFORM_SIMD_CLONES void convolve_rows(const float* const* minus, const float* const* plus, const float* centre, float* o,
                                         int n, const float* taps, int R) {
    int i = 0;
    const v8f zero = splat8(0.f);
    for (; i + 32 <= n; i += 32) {
        v8f a0 = zero, a1 = zero, a2 = zero, a3 = zero;
        if (centre) {
            const v8f k0 = splat8(taps[0]);
            a0 = k0 * load8(centre + i);
            a1 = k0 * load8(centre + i + 8);
            a2 = k0 * load8(centre + i + 16);
            a3 = k0 * load8(centre + i + 24);
        }
        for (int j = 1; j <= R; ++j) {
            const float* m = minus[j];
            const float* p = plus[j];
            const v8f kj = splat8(taps[j]);
            if (m && p) {
                a0 += kj * (load8(m + i) + load8(p + i));
                a1 += kj * (load8(m + i + 8) + load8(p + i + 8));
                a2 += kj * (load8(m + i + 16) + load8(p + i + 16));
                a3 += kj * (load8(m + i + 24) + load8(p + i + 24));
            } else if (m || p) {
                const float* d = m ? m : p;
                a0 += kj * load8(d + i);
                a1 += kj * load8(d + i + 8);
                a2 += kj * load8(d + i + 16);
                a3 += kj * load8(d + i + 24);
            }
        }
        store8(o + i, a0);
        store8(o + i + 8, a1);
        store8(o + i + 16, a2);
        store8(o + i + 24, a3);
    }
    for (; i + 8 <= n; i += 8) {
        v8f a = centre ? splat8(taps[0]) * load8(centre + i) : zero;
        for (int j = 1; j <= R; ++j) {
            const float* m = minus[j];
            const float* p = plus[j];
            if (m && p) a += splat8(taps[j]) * (load8(m + i) + load8(p + i));
            else if (m || p) a += splat8(taps[j]) * load8((m ? m : p) + i);
        }
        store8(o + i, a);
    }
    for (; i < n; ++i) {
        float a = centre ? taps[0] * centre[i] : 0.f;
        for (int j = 1; j <= R; ++j) {
            const float* m = minus[j];
            const float* p = plus[j];
            if (m && p) a += taps[j] * (m[i] + p[i]);
            else if (m || p) a += taps[j] * (m ? m[i] : p[i]);
        }
        o[i] = a;
    }
}

// The extremum scan's two row kernels, 8 lanes at a time like the blur (comparisons and one
// subtraction per lane: the same bits and the same candidates on every CPU).
typedef int v8i __attribute__((vector_size(32)));
inline unsigned mask8(v8i m) {
    v4i lo, hi;
    std::memcpy(&lo, &m, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&m) + sizeof lo, sizeof hi);
    return mask4(lo) | (mask4(hi) << 4);
}

// A DoG row d = t - b over [0, w), and the largest and the smallest of every three neighbours along
// it, mx[i] and mn[i] for i in [1, w - 1).
CANONFORM_SIMD_CLONES void dog_row(const float* b, const float* t, float* d, float* mx, float* mn, int w) {
    int i = 0;
    for (; i + 8 <= w; i += 8) store8(d + i, load8(t + i) - load8(b + i));
    for (; i < w; ++i) d[i] = t[i] - b[i];
    for (i = 1; i + 8 <= w - 1; i += 8) {
        const v8f l = load8(d + i - 1), c = load8(d + i), r = load8(d + i + 1);
        store8(mx + i, l > c ? (l > r ? l : r) : (c > r ? c : r));
        store8(mn + i, l < c ? (l < r ? l : r) : (c < r ? c : r));
    }
    for (; i < w - 1; ++i) {
        mx[i] = std::max(std::max(d[i - 1], d[i]), d[i + 1]);
        mn[i] = std::min(std::min(d[i - 1], d[i]), d[i + 1]);
    }
}

// The positions i in [1, w - 1), ascending, where the DoG row d has a candidate: |d[i]| >= pre,
// d[i] != 0, and d[i] above (below) its 8 neighbours in the layer (the row's neighbours, and the
// rows above and below by their three-neighbour maxima and minima). Returns their number.
CANONFORM_SIMD_CLONES int row_candidates(const float* d, const float* upmax, const float* upmin, const float* downmax,
                                         const float* downmin, int w, float pre, int* out) {
    int n = 0;
    int i = 1;
    const v8f vpre = splat8(pre), vneg = splat8(-pre), vzero = splat8(0.f);
    for (; i + 8 <= w - 1; i += 8) {
        const v8f v = load8(d + i), l = load8(d + i - 1), r = load8(d + i + 1);
        const v8f um = load8(upmax + i), dm = load8(downmax + i), un = load8(upmin + i), dn = load8(downmin + i);
        const v8f hmax = l > r ? l : r, vmax = um > dm ? um : dm, hmin = l < r ? l : r, vmin = un < dn ? un : dn;
        const v8f nmax = hmax > vmax ? hmax : vmax, nmin = hmin < vmin ? hmin : vmin;
        const v8i is = ((v >= vpre) & (v > nmax) & (v != vzero)) | ((v <= vneg) & (v < nmin) & (v != vzero));
        for (unsigned m = mask8(is); m; m &= m - 1) out[n++] = i + __builtin_ctz(m);
    }
    for (; i < w - 1; ++i) {
        const float v = d[i];
        const float nmax = std::max(std::max(d[i - 1], d[i + 1]), std::max(upmax[i], downmax[i]));
        const float nmin = std::min(std::min(d[i - 1], d[i + 1]), std::min(upmin[i], downmin[i]));
        if (v != 0.f && ((v >= pre && v > nmax) || (v <= -pre && v < nmin))) out[n++] = i;
    }
    return n;
}

Workspace& workspace() {
    thread_local Workspace w;
    return w;
}

// out over out.support = in blurred by the kernel (in is 0 outside in.support); out.support must
// lie within in.support grown by the kernel's radius (the rest of the blurred image is dropped, see
// the header). Rows then columns; each output sums k0 v0 + k1 (v-1 + v+1) + ... in that order, so
// the value of a pixel does not depend on where the rectangles lie.
void blur(const Plane& in, Plane& out, const Kernel& k, Workspace& ws) {
    const int R = k.radius;
    const Rect& S = in.support;
    const Rect& O = out.support;
    if (O.empty()) return;
    // Rows are computed in whole blocks of 8: up to 7 values past a row's end, which no reader
    // takes (they fall outside the support; into the next row, which is computed after, or into
    // the 8 spare floats at the end of a plane).
    const int n = (O.width() + 7) & ~7;
    // Horizontal pass into temp rows [ty0, ty1) (the input rows the vertical pass reads).
    const int ty0 = std::max(S.y0, O.y0 - R), ty1 = std::min(S.y1, O.y1 + R);
    const size_t tstride = static_cast<size_t>(n);
    float* temp = ws.temp_for(tstride * static_cast<size_t>(std::max(0, ty1 - ty0)));
    // The input row as a line over [O.x0 - R, O.x1 + R), zero outside S.
    ws.line.assign(static_cast<size_t>(n + 2 * R), 0.f);
    const int lx0 = O.x0 - R;
    const int cx0 = std::max(S.x0, lx0), cx1 = std::min(S.x1, lx0 + n + 2 * R);
    const float* taps = k.taps.data();
    for (int y = ty0; y < ty1; ++y) {
        float* line = ws.line.data();
        if (cx1 > cx0) std::memcpy(line + (cx0 - lx0), in.row(y) + cx0, sizeof(float) * static_cast<size_t>(cx1 - cx0));
        convolve_line(line + R, temp + static_cast<size_t>(y - ty0) * tstride, n, taps, R);
    }
    // Vertical pass: rows outside [ty0, ty1) are 0.
    auto trow = [&](int yy) -> const float* {
        return (yy >= ty0 && yy < ty1) ? temp + static_cast<size_t>(yy - ty0) * tstride : nullptr;
    };
    std::vector<const float*> minus(static_cast<size_t>(R) + 1), plus(static_cast<size_t>(R) + 1);
    for (int y = O.y0; y < O.y1; ++y) {
        for (int j = 1; j <= R; ++j) {
            minus[static_cast<size_t>(j)] = trow(y - j);
            plus[static_cast<size_t>(j)] = trow(y + j);
        }
        convolve_rows(minus.data(), plus.data(), trow(y), out.row(y) + O.x0, n, taps, R);
    }
}

// ---- the extractor --------------------------------------------------------------------------------

constexpr int kOrientationBins = 36;       // Lowe Sec. 5
constexpr double kOrientationSigma = 1.5;  // sigma_w / sigma, Lowe Sec. 5
constexpr double kOrientationRadius = 3;   // window radius / sigma_w (ours)
constexpr double kPeakRatio = 0.8;         // Lowe Sec. 5
constexpr int kGrid = 4;                   // spatial bins per side, Lowe Sec. 6.1
constexpr int kAngles = 8;                 // orientation bins, Lowe Sec. 6.1
constexpr double kBinWidth = 3;            // spatial bin width / sigma (VLFeat's documented magnification)
constexpr float kClip = 0.2f;              // Lowe Sec. 6.1
constexpr int kMaxFits = 5;                // sub-pixel fits per extremum (ours)
constexpr double kPreTest = 0.5;           // |D| >= kPreTest * t before the fit (ours)
constexpr int kMinOctaveSize = 8;          // octaves while the view is at least this wide at the octave
constexpr int kFineLayers = 2;             // DoG images searched in the approximate octave -1 (ours)
constexpr int kOrientationSmoothing = 2;   // passes of [1 2 1] / 4 over the orientation histogram (ours)

struct Settings {
    int layers = 3;
    double sigma0 = 1.6, k = 1, threshold = 0, edge_ratio = 10;
};

struct Candidate {
    SiftKeypoint key;
    int layer = 0;           // Gaussian image j of the octave the keypoint is described in
    int X = 0, Y = 0;        // the sample (octave pixels)
    float fx = 0, fy = 0;    // the sub-pixel offset from it (|f| <= 0.5)
    float sigma = 0;         // scale in octave pixels
};

class Extractor {
public:
    Extractor(const float* image, int size, const Rect& box, const SiftOptions& o) : image_(image), size_(size), box_(box), o_(o) {
        st_.layers = o.octave_layers;
        st_.sigma0 = o.sigma;
        st_.k = exp2_det(1.0 / o.octave_layers);
        st_.threshold = o.contrast_threshold / o.octave_layers;
        st_.edge_ratio = o.edge_threshold;
    }

    SiftFeatures run();

private:
    void stack(const Plane& input, int octaves, int label, float offset);
    void octave(int o, std::vector<Plane>& g, int label, float offset);
    bool refine(const std::vector<Plane>& g, int jmin, int jmax, int& x, int& y, int& j, double off[3],
                double& value) const;
    void orientations(const Plane& L, const Candidate& c, std::vector<double>& angles);
    void descriptor(const Plane& L, const Candidate& c, double angle, float* out);

    const float* image_;
    int size_;
    Rect box_;  // the view's non-zero pixels
    SiftOptions o_;
    Settings st_;
    Workspace& ws_ = workspace();
    std::vector<SiftKeypoint> keys_;
    std::vector<float> ring_;  // the extremum scan's DoG rows
    std::vector<int> hits_;    // the candidates of a DoG row
    std::vector<float> shifted_;  // the view on the doubled image's grid
    std::vector<float> wx_, wy_, dx2_, dy2_;  // window weights
    std::vector<float> desc_;  // 128 per keypoint
};

double layer_sigma(const Settings& st, int j) { return st.sigma0 * exp2_det(double(j) / st.layers); }

SiftFeatures Extractor::run() {
    SiftFeatures out;
    if (box_.empty()) return out;
    const Settings main = st_;
    // The approximate octave -1 (step 1): the view itself, one octave of kFineLayers from sigma / 2.
    if (o_.fine_octave) {
        st_.layers = kFineLayers;
        st_.sigma0 = main.sigma0 / 2;
        Plane view;
        view.data = const_cast<float*>(image_);
        view.frame = {0, 0, size_, size_};
        view.stride = size_;
        view.support = box_;
        stack(view, 1, -1, 0.f);
        st_ = main;
    }
    // Octaves 0 and up on the doubled image's grid: the view linearly interpolated at i - 1/4 on
    // both axes, 0.75 v[i] + 0.25 v[i - 1] (0 outside the view), support one pixel wider.
    const int n = size_ + 1;
    const Rect box{box_.x0, box_.y0, std::min(box_.x1 + 1, n), std::min(box_.y1 + 1, n)};
    shifted_.assign(static_cast<size_t>(n) * static_cast<size_t>(n), 0.f);
    std::vector<float> across(static_cast<size_t>(n));
    for (int y = box.y0; y < box.y1; ++y) {
        float* r = shifted_.data() + static_cast<size_t>(y) * static_cast<size_t>(n);
        const float* v = y < size_ ? image_ + static_cast<size_t>(y) * static_cast<size_t>(size_) : nullptr;
        const float* u = y > 0 ? image_ + static_cast<size_t>(y - 1) * static_cast<size_t>(size_) : nullptr;
        for (int x = box.x0; x < box.x1; ++x) {
            const auto h = [&](const float* row) {  // along the row: 0.75 row[x] + 0.25 row[x - 1]
                if (!row) return 0.f;
                const float here = x < size_ ? row[x] : 0.f, left = x > 0 ? row[x - 1] : 0.f;
                return 0.75f * here + 0.25f * left;
            };
            r[x] = 0.75f * h(v) + 0.25f * h(u);
        }
    }
    Plane grid;
    grid.data = shifted_.data();
    grid.frame = {0, 0, n, n};
    grid.stride = n;
    grid.support = box;
    stack(grid, 1000, 0, 0.25f);
    // max_features: the strongest, in the order found.
    std::vector<size_t> keep(keys_.size());
    for (size_t i = 0; i < keep.size(); ++i) keep[i] = i;
    if (o_.max_features > 0 && keep.size() > static_cast<size_t>(o_.max_features)) {
        std::stable_sort(keep.begin(), keep.end(), [&](size_t a, size_t b) { return keys_[a].response > keys_[b].response; });
        keep.resize(static_cast<size_t>(o_.max_features));
        std::sort(keep.begin(), keep.end());
    }
    out.keypoints.reserve(keep.size());
    out.descriptors.resize(static_cast<Eigen::Index>(keep.size()), 128);
    for (size_t r = 0; r < keep.size(); ++r) {
        out.keypoints.push_back(keys_[keep[r]]);
        std::memcpy(out.descriptors.row(static_cast<Eigen::Index>(r)).data(), desc_.data() + keep[r] * 128, 128 * sizeof(float));
    }
    return out;
}

// One scale space (step 1): from `input` (0 outside its support, blur input_blur), octaves 0 ..
// octaves - 1 of st_'s sampling; keypoints labelled octave `label` + o, at view position
// (octave-0 coordinate) - offset.
void Extractor::stack(const Plane& input, int octaves, int label, float offset) {
    const int jmax = st_.layers + 2;  // Gaussian images j = 0..jmax
    std::vector<Plane> g;
    Rect obj = input.support;
    Plane prev_base;  // octave o's image j = layers (2 sigma0), for octave o + 1 (in the other bank)
    for (int o = 0; o < octaves && ((size_ >> o) >= kMinOctaveSize || o == 0); ++o) {
        const int count = jmax + 1;
        // Supports: the object's box grown by 4 sigma_j; the frame holds the largest.
        const Rect frame = obj.grown(support_radius(layer_sigma(st_, jmax)));
        const size_t cells = static_cast<size_t>(frame.width()) * static_cast<size_t>(frame.height());
        g.assign(static_cast<size_t>(count), Plane{});
        for (int i = 0; i < count; ++i) {
            Plane& p = g[static_cast<size_t>(i)];
            p.data = ws_.plane(o & 1, i, cells + 16);  // (+16: a block of samples may read past a row)
            p.frame = frame;
            p.stride = frame.width();
            p.support = obj.grown(support_radius(layer_sigma(st_, i)));
        }
        Plane& first = g[0];
        if (o == 0) {
            // The input (0 outside it) blurred from input_blur to sigma0.
            const double s = st_.sigma0;
            blur(input, first, gaussian_kernel(std::sqrt(s * s - o_.input_blur * o_.input_blur)), ws_);
        } else {
            // Every second pixel of every second row of the previous octave's image j = layers.
            for (int y = first.support.y0; y < first.support.y1; ++y) {
                float* r = first.row(y);
                const int py = 2 * y;
                const bool row_in = py >= prev_base.support.y0 && py < prev_base.support.y1;
                for (int x = first.support.x0; x < first.support.x1; ++x) {
                    const int px = 2 * x;
                    r[x] = row_in && px >= prev_base.support.x0 && px < prev_base.support.x1 ? prev_base.at(px, py) : 0.f;
                }
            }
        }
        for (int i = 1; i < count; ++i) {
            const double a = layer_sigma(st_, i - 1), b = layer_sigma(st_, i);
            blur(g[static_cast<size_t>(i - 1)], g[static_cast<size_t>(i)], gaussian_kernel(std::sqrt(b * b - a * a)), ws_);
        }
        octave(o, g, label + o, offset);
        // The next octave's base, and its object box (the pixels covering this one's, halved).
        prev_base = g[static_cast<size_t>(st_.layers)];
        const auto half_floor = [](int v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); };
        obj = {half_floor(obj.x0), half_floor(obj.y0), half_floor(obj.x1 - 1) + 1, half_floor(obj.y1 - 1) + 1};
    }
}

// Extrema of the octave's DoG images, refined and tested, then oriented and described.
void Extractor::octave(int o, std::vector<Plane>& g, int label, float offset) {
    const int jmin = 0;
    const int count = static_cast<int>(g.size());
    const int jmax = jmin + count - 1;  // Gaussian j = 0..jmax; DoG j = 0..jmax-1; search 1..jmax-2
    // The view's pixels at this octave (keypoints must lie in the view).
    const Rect inside{0, 0, ((size_ - 1) >> o) + 1, ((size_ - 1) >> o) + 1};
    const float pre = static_cast<float>(kPreTest * st_.threshold);
    const auto G = [&](int j) -> const Plane& { return g[static_cast<size_t>(j - jmin)]; };
    std::vector<Candidate> found;
    for (int j = jmin + 1; j <= jmax - 2; ++j) {
        // Where D_{j-1}, D_j, D_{j+1} are all computed (G_{j-1} has the smallest support).
        const Rect region = G(j - 1).support.grown(-1).meet(inside);
        const Plane &g0 = G(j - 1), &g1 = G(j), &g2 = G(j + 1), &g3 = G(j + 2);
        if (region.empty()) continue;
        // DoG rows y - 1, y, y + 1 of layer j over [x0 - 1, x1 + 1), each with the largest and the
        // smallest of every three neighbours along the row (computed once per row).
        const int x0 = region.x0, x1 = region.x1, w = x1 - x0 + 2;
        const size_t stride = static_cast<size_t>(w);
        ring_.resize(9 * stride);
        auto fill = [&](int slot, int yy) {
            float* d = ring_.data() + static_cast<size_t>(3 * slot) * stride;
            dog_row(g1.row(yy) + x0 - 1, g2.row(yy) + x0 - 1, d, d + stride, d + 2 * stride, w);
        };
        auto slot_of = [&](int yy) { return ((yy % 3) + 3) % 3; };
        fill(slot_of(region.y0 - 1), region.y0 - 1);
        fill(slot_of(region.y0), region.y0);
        hits_.resize(static_cast<size_t>(w));
        for (int y = region.y0; y < region.y1; ++y) {
            fill(slot_of(y + 1), y + 1);
            const float* d = ring_.data() + static_cast<size_t>(3 * slot_of(y)) * stride;
            const float* up = ring_.data() + static_cast<size_t>(3 * slot_of(y - 1)) * stride;
            const float* down = ring_.data() + static_cast<size_t>(3 * slot_of(y + 1)) * stride;
            const int found_here = row_candidates(d, up + stride, up + 2 * stride, down + stride, down + 2 * stride, w, pre,
                                                  hits_.data());
            for (int h = 0; h < found_here; ++h) {
                const int e = hits_[static_cast<size_t>(h)];
                const int x = x0 - 1 + e;
                const float v = d[e];
                // The 18 neighbours in the DoG images j - 1 and j + 1.
                bool extremum = true;
                for (int dy = -1; dy <= 1 && extremum; ++dy) {
                    const float* r0 = g0.row(y + dy);
                    const float* r1 = g1.row(y + dy);
                    const float* r2 = g2.row(y + dy);
                    const float* r3 = g3.row(y + dy);
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx;
                        const float lower = r1[xx] - r0[xx], upper = r3[xx] - r2[xx];
                        if (v > 0 ? (lower >= v || upper >= v) : (lower <= v || upper <= v)) {
                            extremum = false;
                            break;
                        }
                    }
                }
                if (!extremum) continue;
                int X = x, Y = y, J = j;
                double off[3], value = 0;
                if (!refine(g, jmin, jmax, X, Y, J, off, value)) continue;
                Candidate c;
                c.layer = J;
                c.X = X;
                c.Y = Y;
                c.fx = static_cast<float>(off[0]);
                c.fy = static_cast<float>(off[1]);
                c.sigma = static_cast<float>(st_.sigma0 * exp2_det((J + off[2]) / st_.layers));
                const double scale = std::ldexp(1.0, o);
                c.key.x = static_cast<float>((X + off[0]) * scale) - offset;
                c.key.y = static_cast<float>((Y + off[1]) * scale) - offset;
                if (c.key.x < 0 || c.key.y < 0 || c.key.x > size_ - 1 || c.key.y > size_ - 1) continue;
                c.key.size = static_cast<float>(2.0 * c.sigma * scale);
                c.key.octave = label;
                c.key.response = static_cast<float>(std::abs(value));
                found.push_back(c);
            }
        }
    }
    std::vector<double> angles;
    std::array<float, 128> d{};
    for (const Candidate& c : found) {
        const Plane& L = G(c.layer);
        orientations(L, c, angles);
        for (double a : angles) {
            descriptor(L, c, a, d.data());
            SiftKeypoint k = c.key;
            double deg = a * (180.0 / kPi);
            if (deg >= 360.0) deg -= 360.0;
            k.angle = static_cast<float>(deg);
            if (k.angle >= 360.f) k.angle = 0.f;
            keys_.push_back(k);
            desc_.insert(desc_.end(), d.begin(), d.end());
        }
    }
}

// Lowe Sec. 4: fits the quadratic of eq. 2 at (x, y, j), moving the sample while an offset exceeds
// 0.5; then the contrast test and the edge test of Sec. 4.1. True if the extremum is kept.
bool Extractor::refine(const std::vector<Plane>& g, int jmin, int jmax, int& x, int& y, int& j,
                       double off[3], double& value) const {
    const auto D = [&](int jj, int xx, int yy) -> double {
        return double(g[static_cast<size_t>(jj + 1 - jmin)].at(xx, yy)) - double(g[static_cast<size_t>(jj - jmin)].at(xx, yy));
    };
    int px = x, py = y, pj = j;  // the sample before this one
    for (int fit = 0; fit < kMaxFits; ++fit) {
        const double c = D(j, x, y);
        const double gx = 0.5 * (D(j, x + 1, y) - D(j, x - 1, y));
        const double gy = 0.5 * (D(j, x, y + 1) - D(j, x, y - 1));
        const double gs = 0.5 * (D(j + 1, x, y) - D(j - 1, x, y));
        const double hxx = D(j, x + 1, y) + D(j, x - 1, y) - 2 * c;
        const double hyy = D(j, x, y + 1) + D(j, x, y - 1) - 2 * c;
        const double hss = D(j + 1, x, y) + D(j - 1, x, y) - 2 * c;
        const double hxy = 0.25 * (D(j, x + 1, y + 1) - D(j, x - 1, y + 1) - D(j, x + 1, y - 1) + D(j, x - 1, y - 1));
        const double hxs = 0.25 * (D(j + 1, x + 1, y) - D(j + 1, x - 1, y) - D(j - 1, x + 1, y) + D(j - 1, x - 1, y));
        const double hys = 0.25 * (D(j + 1, x, y + 1) - D(j + 1, x, y - 1) - D(j - 1, x, y + 1) + D(j - 1, x, y - 1));
        // x^ = -H^-1 g (eq. 3), by the adjugate.
        const double a00 = hyy * hss - hys * hys, a01 = hxs * hys - hxy * hss, a02 = hxy * hys - hxs * hyy;
        const double a11 = hxx * hss - hxs * hxs, a12 = hxy * hxs - hxx * hys, a22 = hxx * hyy - hxy * hxy;
        const double det = hxx * a00 + hxy * a01 + hxs * a02;
        if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
        off[0] = -(a00 * gx + a01 * gy + a02 * gs) / det;
        off[1] = -(a01 * gx + a11 * gy + a12 * gs) / det;
        off[2] = -(a02 * gx + a12 * gy + a22 * gs) / det;
        if (!std::isfinite(off[0]) || !std::isfinite(off[1]) || !std::isfinite(off[2])) return false;
        // The extremum lies at the fit when every offset is within half a sample (Lowe Sec. 4); also
        // when the move would go back to the sample before (the extremum lies between the two, the
        // fits disagree by a little: ours, accepted within 0.6 of a sample rather than dropped).
        const int mx = off[0] > 0.5 ? 1 : off[0] < -0.5 ? -1 : 0, my = off[1] > 0.5 ? 1 : off[1] < -0.5 ? -1 : 0,
                  mj = off[2] > 0.5 ? 1 : off[2] < -0.5 ? -1 : 0;
        const bool back = fit > 0 && x + mx == px && y + my == py && j + mj == pj && std::abs(off[0]) <= 0.6 &&
                          std::abs(off[1]) <= 0.6 && std::abs(off[2]) <= 0.6;
        if ((mx == 0 && my == 0 && mj == 0) || back) {
            value = c + 0.5 * (gx * off[0] + gy * off[1] + gs * off[2]);  // D(x^)
            if (std::abs(value) < st_.threshold) return false;
            const double tr = hxx + hyy, dt = hxx * hyy - hxy * hxy;
            const double r = st_.edge_ratio;
            return dt > 0 && tr * tr * r < (r + 1) * (r + 1) * dt;
        }
        // Move one sample towards the offset in each coordinate beyond 0.5; stay where all three
        // DoG images are computed.
        px = x;
        py = y;
        pj = j;
        x += mx;
        y += my;
        j += mj;
        if (j < jmin + 1 || j > jmax - 2) return false;
        const Rect region = g[static_cast<size_t>(j - 1 - jmin)].support.grown(-1);
        if (x < region.x0 || x >= region.x1 || y < region.y0 || y >= region.y1) return false;
    }
    return false;
}

// The pixels of L within `radius` of the keypoint (a square, inside L's support less one pixel, so
// that central differences stay in it): [x0, x1] x [y0, y1].
Rect window(const Plane& L, const Candidate& c, double radius) {
    const Rect inner = L.support.grown(-1);
    return {std::max(inner.x0, c.X + static_cast<int>(std::ceil(c.fx - radius))),
            std::max(inner.y0, c.Y + static_cast<int>(std::ceil(c.fy - radius))),
            std::min(inner.x1 - 1, c.X + static_cast<int>(std::floor(c.fx + radius))),
            std::min(inner.y1 - 1, c.Y + static_cast<int>(std::floor(c.fy + radius)))};
}

// Sampling of the orientation and descriptor windows: every p-th pixel of every p-th row (aligned
// on the keypoint's sample), p = max(1, round(w / 4)) for the descriptor's bin width w = 3 sigma:
// about 4 x 4 samples per bin (at least 3), as Lowe's 16 x 16 sample array over 4 x 4 bins (Sec. 6.1).
int sample_step(float sigma) { return std::max(1, static_cast<int>(kBinWidth * double(sigma) / 4.0 + 0.5)); }

// Lowe Sec. 5: the orientations (radians, [0, 2 pi)) of a keypoint from the histogram of gradient
// directions in L around it. Offsets are taken from the sample (integer) and then the sub-pixel
// part, so that the result does not depend on where the object lies in the view.
void Extractor::orientations(const Plane& L, const Candidate& c, std::vector<double>& angles) {
    angles.clear();
    const double sw = kOrientationSigma * c.sigma, radius = kOrientationRadius * sw;
    const Rect win = window(L, c, radius);
    const int x0 = win.x0, x1 = win.x1, y0 = win.y0, y1 = win.y1;
    if (x0 > x1 || y0 > y1) return;
    // Separable Gaussian weights (the window is a disk: radius^2 >= dx^2 + dy^2).
    const size_t nx = static_cast<size_t>(x1 - x0 + 1), ny = static_cast<size_t>(y1 - y0 + 1);
    wx_.resize(nx + 16);
    dx2_.resize(nx + 16);
    wy_.resize(ny);
    dy2_.resize(ny);
    const double inv = -1.0 / (2.0 * sw * sw);
    for (size_t i = 0; i < nx + 16; ++i) {  // (more for the last block of four samples)
        const double d = double(x0 + static_cast<int>(i) - c.X) - double(c.fx);
        dx2_[i] = static_cast<float>(d * d);
        wx_[i] = static_cast<float>(exp_det(d * d * inv));
    }
    for (size_t i = 0; i < ny; ++i) {
        const double d = double(y0 + static_cast<int>(i) - c.Y) - double(c.fy);
        dy2_[i] = static_cast<float>(d * d);
        wy_[i] = static_cast<float>(exp_det(d * d * inv));
    }
    const float r2 = static_cast<float>(radius * radius);
    float hist[kOrientationBins] = {};
    const float to_bin = static_cast<float>(kOrientationBins / (2 * kPi));
    alignas(16) float wv[4], bv[4];
    const int p = sample_step(c.sigma);
    for (int y = align_up(y0, c.Y, p); y <= y1; y += p) {
        const float* up = L.row(y - 1);
        const float* mid = L.row(y);
        const float* down = L.row(y + 1);
        const float wyy = wy_[static_cast<size_t>(y - y0)], dyy = dy2_[static_cast<size_t>(y - y0)];
        for (int x = align_up(x0, c.X, p); x <= x1; x += 4 * p) {
            // Four samples at once (lanes past x1 are masked out): weight m * w, bin position.
            const size_t i = static_cast<size_t>(x - x0);
            const v4f gx = load4s(mid + x + 1, p) - load4s(mid + x - 1, p), gy = load4s(down + x, p) - load4s(up + x, p);
            const v4f m = sqrt4(gx * gx + gy * gy);
            const v4i in = (load4s(dx2_.data() + i, p) + splat4(dyy) <= splat4(r2)) & (m > splat4(0.f)) &
                           (v4i{0, 1, 2, 3} * splat4i(p) <= splat4i(x1 - x));
            if (!mask4(in)) continue;
            store4(wv, select4(in, m * (load4s(wx_.data() + i, p) * splat4(wyy)), splat4(0.f)));
            store4(bv, atan2_det4(gy, gx) * splat4(to_bin));
            for (int q = 0; q < 4; ++q) {
                if (!in[q]) continue;
                const float w = wv[q], b = bv[q];
                int b0 = static_cast<int>(b);  // b >= 0
                const float f = b - static_cast<float>(b0);
                if (b0 >= kOrientationBins) b0 -= kOrientationBins;
                hist[b0] += (1.f - f) * w;
                hist[b0 + 1 == kOrientationBins ? 0 : b0 + 1] += f * w;
            }
        }
    }
    // Smoothed by a Gaussian of one bin (two passes of the circular [1 2 1] / 4).
    for (int pass = 0; pass < kOrientationSmoothing; ++pass) {
        float smooth[kOrientationBins];
        for (int i = 0; i < kOrientationBins; ++i)
            smooth[i] = 0.25f * (hist[(i + kOrientationBins - 1) % kOrientationBins] + hist[(i + 1) % kOrientationBins]) +
                        0.5f * hist[i];
        std::copy(smooth, smooth + kOrientationBins, hist);
    }
    float top = 0;
    for (float h : hist) top = std::max(top, h);
    if (!(top > 0.f)) return;
    for (int i = 0; i < kOrientationBins; ++i) {
        const float l = hist[(i + kOrientationBins - 1) % kOrientationBins], h = hist[i], r = hist[(i + 1) % kOrientationBins];
        if (!(h > l && h > r && h >= static_cast<float>(kPeakRatio) * top)) continue;
        const double delta = 0.5 * (double(l) - double(r)) / (double(l) - 2.0 * double(h) + double(r));
        double a = (i + delta) * (2 * kPi / kOrientationBins);
        if (a < 0) a += 2 * kPi;
        if (a >= 2 * kPi) a -= 2 * kPi;
        angles.push_back(a);
    }
}

// The x range [lo, hi] (offsets from the keypoint's sample, widened by a pixel) where
// -1 < a dx + b < 4 can hold, intersected with [lo, hi]: the descriptor's rotated square on a row.
void narrow(double a, double b, double& lo, double& hi) {
    if (std::abs(a) < 1e-12) {
        if (!(b > -1.0 && b < kGrid)) hi = lo - 1;
        return;
    }
    double u = (-1.0 - b) / a, v = (kGrid - b) / a;
    if (u > v) std::swap(u, v);
    lo = std::max(lo, std::floor(u) - 1);
    hi = std::min(hi, std::ceil(v) + 1);
}

// Lowe Sec. 6.1: the 128 values of a keypoint with orientation `angle` (radians).
void Extractor::descriptor(const Plane& L, const Candidate& k, double angle, float* out) {
    const double w = kBinWidth * k.sigma;               // spatial bin width (octave pixels)
    const double half = (kGrid / 2.0 + 0.5) * w;        // half the grid plus half a bin
    const double radius = half * 1.4142135623730951;    // the rotated square's circumradius
    const Rect win = window(L, k, radius);
    const int x0 = win.x0, x1 = win.x1, y0 = win.y0, y1 = win.y1;
    // Histogram with a border of one bin on every side (rows and columns -1..4) for the spread.
    constexpr int kSide = kGrid + 2;
    float hist[kSide * kSide * kAngles] = {};
    if (x0 <= x1 && y0 <= y1) {
        double sd, cd;
        sincos_det(angle, sd, cd);
        const float c = static_cast<float>(cd / w), s = static_cast<float>(sd / w);
        const float centre = static_cast<float>(kGrid / 2.0 - 0.5);  // bin centres at 0..3
        const size_t nx = static_cast<size_t>(x1 - x0 + 1), ny = static_cast<size_t>(y1 - y0 + 1);
        wx_.resize(nx + 16);
        wy_.resize(ny);
        const double sigma_w = 0.5 * kGrid * w;  // half the grid's width (Lowe)
        const double inv = -1.0 / (2.0 * sigma_w * sigma_w);
        for (size_t i = 0; i < nx + 16; ++i) {
            const double d = double(x0 + static_cast<int>(i) - k.X) - double(k.fx);
            wx_[i] = static_cast<float>(exp_det(d * d * inv));
        }
        for (size_t i = 0; i < ny; ++i) {
            const double d = double(y0 + static_cast<int>(i) - k.Y) - double(k.fy);
            wy_[i] = static_cast<float>(exp_det(d * d * inv));
        }
        const float to_bin = static_cast<float>(kAngles / (2 * kPi));
        const float a0 = static_cast<float>(angle);
        const float two_pi = static_cast<float>(2 * kPi);
        alignas(16) float wv[4], colv[4], rowv[4], obv[4];
        const int p = sample_step(k.sigma);
        for (int y = align_up(y0, k.Y, p); y <= y1; y += p) {
            const float* up = L.row(y - 1);
            const float* mid = L.row(y);
            const float* down = L.row(y + 1);
            const float dy = static_cast<float>(y - k.Y) - k.fy;
            const float wyy = wy_[static_cast<size_t>(y - y0)];
            // Only the pixels near the rotated square (the test below decides).
            double lo = x0 - k.X, hi = x1 - k.X;
            narrow(c, double(s) * dy + centre, lo, hi);
            narrow(-double(s), double(c) * dy + centre, lo, hi);
            const int xa = align_up(k.X + static_cast<int>(lo), k.X, p), xb = k.X + static_cast<int>(hi);
            const v4f lane = v4f{0.f, 1.f, 2.f, 3.f} * splat4(float(p));
            for (int x = xa; x <= xb; x += 4 * p) {
                const size_t i = static_cast<size_t>(x - x0);
                const v4f dx = (splat4(static_cast<float>(x - k.X)) + lane) - splat4(k.fx);
                const v4f col = splat4(c) * dx + splat4(s * dy) + splat4(centre);   // along the keypoint's direction
                const v4f row = splat4(-s) * dx + splat4(c * dy) + splat4(centre);  // 90 degrees clockwise from it
                const v4f gx = load4s(mid + x + 1, p) - load4s(mid + x - 1, p), gy = load4s(down + x, p) - load4s(up + x, p);
                const v4f m = sqrt4(gx * gx + gy * gy);
                const v4i in = (col > splat4(-1.f)) & (col < splat4(float(kGrid))) & (row > splat4(-1.f)) &
                               (row < splat4(float(kGrid))) & (m > splat4(0.f)) & (v4i{0, 1, 2, 3} * splat4i(p) <= splat4i(xb - x));
                if (!mask4(in)) continue;
                v4f phi = splat4(a0) - atan2_det4(gy, gx);  // counted anticlockwise on screen (OpenCV's order)
                phi = select4(phi < splat4(0.f), phi + splat4(two_pi), phi);
                v4f ob = phi * splat4(to_bin);
                ob = select4(ob >= splat4(float(kAngles)), ob - splat4(float(kAngles)), ob);
                store4(wv, m * (load4s(wx_.data() + i, p) * splat4(wyy)));
                store4(colv, col);
                store4(rowv, row);
                store4(obv, ob);
                for (int q = 0; q < 4; ++q) {
                    if (!in[q]) continue;
                    const float weight = wv[q], rw = rowv[q], cl = colv[q], obq = obv[q];
                    const int r0 = static_cast<int>(std::floor(rw)), c0 = static_cast<int>(std::floor(cl));
                    int o0 = static_cast<int>(obq);
                    const float fr = rw - static_cast<float>(r0), fc = cl - static_cast<float>(c0), fo = obq - static_cast<float>(o0);
                    if (o0 >= kAngles) o0 -= kAngles;
                    const int o1 = o0 + 1 == kAngles ? 0 : o0 + 1;
                    for (int dr = 0; dr < 2; ++dr) {
                        const float wr = weight * (dr ? fr : 1.f - fr);
                        float* hr = hist + ((r0 + dr + 1) * kSide) * kAngles;
                        for (int dc = 0; dc < 2; ++dc) {
                            const float wc = wr * (dc ? fc : 1.f - fc);
                            float* h = hr + (c0 + dc + 1) * kAngles;
                            h[o0] += wc * (1.f - fo);
                            h[o1] += wc * fo;
                        }
                    }
                }
            }
        }
    }
    // The inner 4 x 4 bins; unit length, clipped at 0.2, unit length again (Lowe Sec. 6.1).
    float v[128];
    for (int r = 0; r < kGrid; ++r)
        for (int c = 0; c < kGrid; ++c)
            for (int a = 0; a < kAngles; ++a) v[(r * kGrid + c) * kAngles + a] = hist[((r + 1) * kSide + c + 1) * kAngles + a];
    float n2 = 0;
    for (float x : v) n2 += x * x;
    if (n2 > 0.f) {
        const float inv = 1.f / std::sqrt(n2);
        n2 = 0;
        for (float& x : v) {
            x = std::min(x * inv, kClip);
            n2 += x * x;
        }
        const float scale = 512.f / std::sqrt(n2);
        for (int i = 0; i < 128; ++i) out[i] = std::min(255.f, std::floor(v[i] * scale + 0.5f));
    } else {
        for (int i = 0; i < 128; ++i) out[i] = 0.f;
    }
}

// One pass over an image: whether every value is finite, whether all are equal, and the box of the
// non-zero pixels.
struct ImageScan {
    bool finite = true, constant = true;
    Rect box;
};

ImageScan scan_image(const float* v, int size) {
    ImageScan r;
    r.box = {size, size, 0, 0};
    const v4f zero = splat4(0.f), first = splat4(v[0]);
    v4f nan_check = zero;  // v - v is 0 for finite v, NaN otherwise
    unsigned differs = 0;
    for (int y = 0; y < size; ++y) {
        const float* row = v + static_cast<size_t>(y) * static_cast<size_t>(size);
        int lo = -1, hi = -1, x = 0;
        for (; x + 4 <= size; x += 4) {
            const v4f q = load4(row + x);
            nan_check += q - q;
            differs |= mask4(q != first);
            const unsigned m = mask4(q != zero);
            if (m) {
                if (lo < 0) lo = x + __builtin_ctz(m);
                hi = x + 31 - __builtin_clz(m);
            }
        }
        for (; x < size; ++x) {
            r.finite = r.finite && std::isfinite(row[x]);
            differs |= row[x] != v[0] ? 1u : 0u;
            if (row[x] != 0.f) {
                if (lo < 0) lo = x;
                hi = x;
            }
        }
        if (lo < 0) continue;
        r.box = {std::min(r.box.x0, lo), std::min(r.box.y0, y), std::max(r.box.x1, hi + 1), std::max(r.box.y1, y + 1)};
    }
    r.finite = r.finite && mask4(nan_check == zero) == 15u;
    r.constant = differs == 0;
    return r;
}

void check_size(size_t have, int size, const char* unit) {
    if (size <= 0) throw InputError("SIFT: the image size must be positive (got " + std::to_string(size) + ").");
    const size_t expected = static_cast<size_t>(size) * static_cast<size_t>(size);
    if (have != expected)
        throw InputError("SIFT: the image buffer has " + std::to_string(have) + " " + unit + ", expected " +
                         std::to_string(expected) + " for a " + std::to_string(size) + " x " +
                         std::to_string(size) + " image.");
}

void check_options(const SiftOptions& o) {
    if (!(o.contrast_threshold >= 0) || !std::isfinite(o.contrast_threshold))
        throw InputError("SIFT: contrast_threshold must be a finite value >= 0.");
    if (!(o.edge_threshold > 0) || !std::isfinite(o.edge_threshold))
        throw InputError("SIFT: edge_threshold must be a finite value > 0.");
    if (!(o.sigma > 0) || !std::isfinite(o.sigma)) throw InputError("SIFT: sigma must be > 0.");
    if (o.octave_layers < 1 || o.octave_layers > 16) throw InputError("SIFT: octave_layers must be in 1..16.");
    if (o.max_features < 0) throw InputError("SIFT: max_features must be >= 0 (0 = all).");
    if (!(o.input_blur >= 0) || !(o.input_blur < 0.5 * o.sigma))
        throw InputError("SIFT: input_blur must be >= 0 and below sigma / 2.");
    if (!sift_backend_available(o.backend)) {
        std::string have;
        for (const auto& n : sift_backend_names())
            if (sift_backend_available(parse_sift_backend(n))) have += (have.empty() ? "" : ", ") + n;
        throw InputError("SIFT: the backend '" + sift_backend_name(o.backend) + "' is not part of this program (" + have +
                         " are; opencv is in the canonform tool).");
    }
}

}  // namespace

SiftFeatures sift_features(const std::vector<float>& image, int size, const SiftOptions& options) {
    check_size(image.size(), size, "values");
    check_options(options);
    const ImageScan scan = scan_image(image.data(), size);
    if (!scan.finite) throw InputError("SIFT: the image has a non-finite value.");
    if (scan.constant) return {};
    if (options.backend != SiftBackend::Canonform)
        return g_extractors.at(static_cast<size_t>(options.backend)).load()(image, size, options);
    return Extractor(image.data(), size, scan.box, options).run();
}

SiftDescriptors sift_descriptors(const std::vector<float>& image, int size, const SiftOptions& options) {
    return sift_features(image, size, options).descriptors;
}

SiftFeatures sift_features(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    check_size(gray.size(), size, "bytes");
    std::vector<float> image(gray.size());
    for (size_t i = 0; i < gray.size(); ++i) image[i] = static_cast<float>(gray[i]) / 255.f;
    return sift_features(image, size, options);
}

SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    return sift_features(gray, size, options).descriptors;
}

SiftFeatures depth_sift_features(const std::vector<float>& depth, int size, const SiftOptions& options) {
    check_size(depth.size(), size, "values");
    // The 8-bit view, round(255 depth) / 255, for both extractors (step 1).
    // round(x) for x = 255 clamp(depth) in [0, 255] is the truncation of x + 0.5: x, 255 times a
    // float, has at most 32 significant bits, so x + 0.5 is exact unless x < 2^-14, where both are
    // 0 (checked for every float in [0, 1]). A NaN stays NaN (sift_features refuses it).
    std::vector<float> image(depth.size());
    for (size_t i = 0; i < depth.size(); ++i) {
        const double x = 255.0 * std::clamp(static_cast<double>(depth[i]), 0.0, 1.0);
        image[i] = x == x ? static_cast<float>(static_cast<int>(x + 0.5)) / 255.f : std::numeric_limits<float>::quiet_NaN();
    }
    return sift_features(image, size, options);
}

SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size, const SiftOptions& options) {
    return depth_sift_features(depth, size, options).descriptors;
}

}  // namespace canonform::views
