// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/sift_pyramid.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/numerics/portable_math.h"
#include "canonform/views/sift_simd.h"

#include <cmath>
#include <cstring>
#ifdef CANONFORM_CPU_DISPATCH
#include <immintrin.h>
#endif

namespace canonform::views {
namespace sift {

int support_radius(double sigma) {
    return std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
}

Kernel gaussian_kernel(double sigma) {
    Kernel k;
    k.radius = support_radius(sigma);
    std::vector<double> w(static_cast<size_t>(k.radius) + 1);
    double sum = 0;
    for (int j = 0; j <= k.radius; ++j) {
        w[static_cast<size_t>(j)] = numerics::portable_exp(-double(j) * double(j) / (2.0 * sigma * sigma));
        sum += (j == 0 ? 1.0 : 2.0) * w[static_cast<size_t>(j)];
    }
    for (double v : w) k.taps.push_back(static_cast<float>(v / sum));
    return k;
}

float* Workspace::plane(int bank, int slot, size_t n) {
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

const Kernel& Workspace::kernel(double sigma) {
    for (const auto& [s, k] : kernels)
        if (s == sigma) return k;
    if (kernels.size() >= 64) kernels.clear();  // settings changed many times in this thread
    kernels.emplace_back(sigma, gaussian_kernel(sigma));
    return kernels.back().second;
}

float* Workspace::temp_for(size_t n) {
    if (n > temp_size) {
        temp.reset(new float[n]);
        temp_size = n;
    }
    return temp.get();
}

Workspace& workspace() {
    thread_local Workspace w;
    return w;
}

namespace {

// The two passes of the blur below, in blocks of 64 floats as four 16-float vectors (four sums in
// flight: each tap's addition waits for the one before), then 32 as two (sift_simd.h:
// 16-lane AVX-512 instructions in the x86-64-v4 clone, pairs of 8-lane AVX2 ones in the AVX2 clone,
// four 4-lane SSE2 ones elsewhere: the same bits), then 8 at a time.

// o[i] = k0 c[i] + k1 (c[i-1] + c[i+1]) + ... + kR (c[i-R] + c[i+R]) for i in [0, n), summed in
// that order (c must be readable at [-R, n + R)).
CANONFORM_CLONES_AVX512 void convolve_line(const float* c, float* o, int n, const float* taps, int R) {
    int i = 0;
    for (; i + 64 <= n; i += 64) {
        const v16f k0 = splat16(taps[0]);
        v16f a0 = k0 * load16(c + i), a1 = k0 * load16(c + i + 16), a2 = k0 * load16(c + i + 32),
             a3 = k0 * load16(c + i + 48);
        for (int j = 1; j <= R; ++j) {
            const v16f kj = splat16(taps[j]);
            a0 += kj * (load16(c + i - j) + load16(c + i + j));
            a1 += kj * (load16(c + i + 16 - j) + load16(c + i + 16 + j));
            a2 += kj * (load16(c + i + 32 - j) + load16(c + i + 32 + j));
            a3 += kj * (load16(c + i + 48 - j) + load16(c + i + 48 + j));
        }
        store16(o + i, a0);
        store16(o + i + 16, a1);
        store16(o + i + 32, a2);
        store16(o + i + 48, a3);
    }
    for (; i + 32 <= n; i += 32) {
        const v16f k0 = splat16(taps[0]);
        v16f a0 = k0 * load16(c + i), a1 = k0 * load16(c + i + 16);
        for (int j = 1; j <= R; ++j) {
            const v16f kj = splat16(taps[j]);
            a0 += kj * (load16(c + i - j) + load16(c + i + j));
            a1 += kj * (load16(c + i + 16 - j) + load16(c + i + 16 + j));
        }
        store16(o + i, a0);
        store16(o + i + 16, a1);
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

// o[i] = k0 r0[i] + k1 (m1[i] + p1[i]) + ... over rows r0 = at[0], m_j = at[-j], p_j = at[j], where a
// null row is 0 and its terms are left out (adding 0 changes no sum).
CANONFORM_CLONES_AVX512 void convolve_rows(const float* const* at, float* o, int n, const float* taps,
                                           int R) {
    const float* const centre = at[0];
    const float* const* const plus = at;
    const auto minus = [at](int j) { return at[-j]; };
    int i = 0;
    const v8f zero = splat8(0.f);
    const v16f zero16 = splat16(0.f);
    for (; i + 64 <= n; i += 64) {
        v16f a0 = zero16, a1 = zero16, a2 = zero16, a3 = zero16;
        if (centre) {
            const v16f k0 = splat16(taps[0]);
            a0 = k0 * load16(centre + i);
            a1 = k0 * load16(centre + i + 16);
            a2 = k0 * load16(centre + i + 32);
            a3 = k0 * load16(centre + i + 48);
        }
        for (int j = 1; j <= R; ++j) {
            const float* m = minus(j);
            const float* p = plus[j];
            const v16f kj = splat16(taps[j]);
            if (m && p) {
                a0 += kj * (load16(m + i) + load16(p + i));
                a1 += kj * (load16(m + i + 16) + load16(p + i + 16));
                a2 += kj * (load16(m + i + 32) + load16(p + i + 32));
                a3 += kj * (load16(m + i + 48) + load16(p + i + 48));
            } else if (m || p) {
                const float* d = m ? m : p;
                a0 += kj * load16(d + i);
                a1 += kj * load16(d + i + 16);
                a2 += kj * load16(d + i + 32);
                a3 += kj * load16(d + i + 48);
            }
        }
        store16(o + i, a0);
        store16(o + i + 16, a1);
        store16(o + i + 32, a2);
        store16(o + i + 48, a3);
    }
    for (; i + 32 <= n; i += 32) {
        v16f a0 = zero16, a1 = zero16;
        if (centre) {
            const v16f k0 = splat16(taps[0]);
            a0 = k0 * load16(centre + i);
            a1 = k0 * load16(centre + i + 16);
        }
        for (int j = 1; j <= R; ++j) {
            const float* m = minus(j);
            const float* p = plus[j];
            const v16f kj = splat16(taps[j]);
            if (m && p) {
                a0 += kj * (load16(m + i) + load16(p + i));
                a1 += kj * (load16(m + i + 16) + load16(p + i + 16));
            } else if (m || p) {
                const float* d = m ? m : p;
                a0 += kj * load16(d + i);
                a1 += kj * load16(d + i + 16);
            }
        }
        store16(o + i, a0);
        store16(o + i + 16, a1);
    }
    for (; i + 8 <= n; i += 8) {
        v8f a = centre ? splat8(taps[0]) * load8(centre + i) : zero;
        for (int j = 1; j <= R; ++j) {
            const float* m = minus(j);
            const float* p = plus[j];
            if (m && p)
                a += splat8(taps[j]) * (load8(m + i) + load8(p + i));
            else if (m || p)
                a += splat8(taps[j]) * load8((m ? m : p) + i);
        }
        store8(o + i, a);
    }
    for (; i < n; ++i) {
        float a = centre ? taps[0] * centre[i] : 0.f;
        for (int j = 1; j <= R; ++j) {
            const float* m = minus(j);
            const float* p = plus[j];
            if (m && p)
                a += taps[j] * (m[i] + p[i]);
            else if (m || p)
                a += taps[j] * (m ? m[i] : p[i]);
        }
        o[i] = a;
    }
}

}  // namespace

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
        if (cx1 > cx0)
            std::memcpy(line + (cx0 - lx0), in.row(y) + cx0, sizeof(float) * static_cast<size_t>(cx1 - cx0));
        convolve_line(line + R, temp + static_cast<size_t>(y - ty0) * tstride, n, taps, R);
    }
    // Vertical pass: rows outside [ty0, ty1) are 0.
    auto trow = [&](int yy) -> const float* {
        return (yy >= ty0 && yy < ty1) ? temp + static_cast<size_t>(yy - ty0) * tstride : nullptr;
    };
    // The temp rows y - R .. y + R of every output row y, set up once: rows[R + y - O.y0 + d] is row y + d.
    std::vector<const float*>& rows = ws.rows;
    rows.resize(static_cast<size_t>(O.height() + 2 * R));
    for (int yy = O.y0 - R; yy < O.y1 + R; ++yy) rows[static_cast<size_t>(yy - (O.y0 - R))] = trow(yy);
    for (int y = O.y0; y < O.y1; ++y) {
        const float* const* at = rows.data() + (y - O.y0 + R);
        convolve_rows(at, out.row(y) + O.x0, n, taps, R);
    }
}

double layer_sigma(const Settings& st, int j) {
    return st.sigma0 * numerics::portable_exp2(double(j) / st.layers);
}

void gaussian_octave(int o, const Rect& obj, const Plane& source, double input_blur, const Settings& st,
                     Workspace& ws, std::vector<Plane>& g) {
    const int count = st.layers + 3;
    // Supports: the object's box grown by 3 sigma_j; the frame holds the largest.
    const Rect frame = obj.grown(support_radius(layer_sigma(st, count - 1)));
    const size_t cells = static_cast<size_t>(frame.width()) * static_cast<size_t>(frame.height());
    g.assign(static_cast<size_t>(count), Plane{});
    for (int i = 0; i < count; ++i) {
        Plane& p = g[static_cast<size_t>(i)];
        p.data = ws.plane(o & 1, i, cells + 16);  // (+16: a block of samples may read past a row)
        p.frame = frame;
        p.stride = frame.width();
        p.support = obj.grown(support_radius(layer_sigma(st, i)));
    }
    // The last image enters only the top DoG image, which is read (by the extremum scan and the fit
    // of the highest searched layer, count - 3) within image count - 4's support: it is computed
    // there only. A pixel's value does not depend on the rectangle it is computed in (blur).
    if (count >= 4) g[static_cast<size_t>(count - 1)].support = g[static_cast<size_t>(count - 4)].support;
    Plane& first = g[0];
    if (o == 0) {
        // The input (0 outside it) blurred from input_blur to sigma0.
        const double s = st.sigma0;
        blur(source, first, ws.kernel(std::sqrt(s * s - input_blur * input_blur)), ws);
    } else {
        // Every second pixel of every second row of the previous octave's image j = layers.
        for (int y = first.support.y0; y < first.support.y1; ++y) {
            float* r = first.row(y);
            const int py = 2 * y;
            const bool row_in = py >= source.support.y0 && py < source.support.y1;
            for (int x = first.support.x0; x < first.support.x1; ++x) {
                const int px = 2 * x;
                r[x] = row_in && px >= source.support.x0 && px < source.support.x1 ? source.at(px, py) : 0.f;
            }
        }
    }
    for (int i = 1; i < count; ++i) {
        const double a = layer_sigma(st, i - 1), b = layer_sigma(st, i);
        blur(g[static_cast<size_t>(i - 1)], g[static_cast<size_t>(i)], ws.kernel(std::sqrt(b * b - a * a)),
             ws);
    }
}

// The extremum scan's two row kernels, 8 lanes at a time like the blur (comparisons and one
// subtraction per lane: the same bits and the same candidates on every CPU), or 16 with AVX-512
// below.

CANONFORM_CLONES void dog_row_portable(const float* b, const float* t, float* d, float* mx, float* mn,
                                       int w) {
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

CANONFORM_CLONES int row_candidates_portable(const float* d, const float* upmax, const float* upmin,
                                             const float* downmax, const float* downmin, int w, float pre,
                                             int* out) {
    int n = 0;
    int i = 1;
    const v8f vpre = splat8(pre), vneg = splat8(-pre), vzero = splat8(0.f);
    for (; i + 8 <= w - 1; i += 8) {
        const v8f v = load8(d + i), l = load8(d + i - 1), r = load8(d + i + 1);
        const v8f um = load8(upmax + i), dm = load8(downmax + i), un = load8(upmin + i),
                  dn = load8(downmin + i);
        const v8f hmax = l > r ? l : r, vmax = um > dm ? um : dm, hmin = l < r ? l : r,
                  vmin = un < dn ? un : dn;
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

namespace {

#ifdef CANONFORM_CPU_DISPATCH
// The same two kernels with AVX-512's comparisons into mask registers, 16 lanes a step and the
// row's last lanes under a mask (masked loads do not read past the row). GCC's vector extension
// turns a 16-lane comparison's result into a mask lane by lane, so these are written with the
// CPU's intrinsics and chosen at run time (scan_avx512 below). The DoG values are the same
// subtractions; the maxima and minima are the same values (only the sign of a zero may differ,
// which no comparison below sees), so the candidates are the same.
// (_mm512_max_ps and _mm512_min_ps through their masked forms: GCC 12 warns that the plain ones
// read an undefined value.)
__attribute__((target("avx512f"))) inline __m512 max16(__m512 a, __m512 b) {
    return _mm512_mask_max_ps(a, 0xffff, a, b);
}
__attribute__((target("avx512f"))) inline __m512 min16(__m512 a, __m512 b) {
    return _mm512_mask_min_ps(a, 0xffff, a, b);
}

__attribute__((target("avx512f"))) void dog_row_avx512(const float* b, const float* t, float* d, float* mx,
                                                       float* mn, int w) {
    for (int i = 0; i < w; i += 16) {
        const __mmask16 k = w - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (w - i)) - 1);
        _mm512_mask_storeu_ps(
            d + i, k, _mm512_sub_ps(_mm512_maskz_loadu_ps(k, t + i), _mm512_maskz_loadu_ps(k, b + i)));
    }
    for (int i = 1; i < w - 1; i += 16) {
        const __mmask16 k = w - 1 - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (w - 1 - i)) - 1);
        const __m512 l = _mm512_maskz_loadu_ps(k, d + i - 1), c = _mm512_maskz_loadu_ps(k, d + i),
                     r = _mm512_maskz_loadu_ps(k, d + i + 1);
        _mm512_mask_storeu_ps(mx + i, k, max16(max16(l, c), r));
        _mm512_mask_storeu_ps(mn + i, k, min16(min16(l, c), r));
    }
}

__attribute__((target("avx512f"))) int row_candidates_avx512(const float* d, const float* upmax,
                                                             const float* upmin, const float* downmax,
                                                             const float* downmin, int w, float pre,
                                                             int* out) {
    int n = 0;
    const __m512 vpre = _mm512_set1_ps(pre), vneg = _mm512_set1_ps(-pre), zero = _mm512_setzero_ps();
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    for (int i = 1; i < w - 1; i += 16) {
        const __mmask16 k = w - 1 - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (w - 1 - i)) - 1);
        const __m512 v = _mm512_maskz_loadu_ps(k, d + i), l = _mm512_maskz_loadu_ps(k, d + i - 1),
                     r = _mm512_maskz_loadu_ps(k, d + i + 1);
        const __m512 nmax = max16(
            max16(l, r), max16(_mm512_maskz_loadu_ps(k, upmax + i), _mm512_maskz_loadu_ps(k, downmax + i)));
        const __m512 nmin = min16(
            min16(l, r), min16(_mm512_maskz_loadu_ps(k, upmin + i), _mm512_maskz_loadu_ps(k, downmin + i)));
        const __mmask16 above =
            _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(v, vpre, _CMP_GE_OQ), v, nmax, _CMP_GT_OQ);
        const __mmask16 below =
            _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(v, vneg, _CMP_LE_OQ), v, nmin, _CMP_LT_OQ);
        const __mmask16 is = _mm512_mask_cmp_ps_mask(k & (above | below), v, zero, _CMP_NEQ_UQ);
        // The lanes' positions packed to the front and stored whole (no branch on where
        // candidates fall: out has 16 spare ints).
        const __m512i at = _mm512_add_epi32(_mm512_set1_epi32(i), lane);
        _mm512_storeu_si512(out + n, _mm512_maskz_compress_epi32(is, at));
        n += __builtin_popcount(is);
    }
    return n;
}

bool scan_avx512() {
    static const bool yes = __builtin_cpu_supports("avx512f");
    return yes;
}
#endif

}  // namespace

void dog_row(const float* b, const float* t, float* d, float* mx, float* mn, int w) {
#ifdef CANONFORM_CPU_DISPATCH
    if (scan_avx512()) return dog_row_avx512(b, t, d, mx, mn, w);
#endif
    dog_row_portable(b, t, d, mx, mn, w);
}

int row_candidates(const float* d, const float* upmax, const float* upmin, const float* downmax,
                   const float* downmin, int w, float pre, int* out) {
#ifdef CANONFORM_CPU_DISPATCH
    if (scan_avx512()) return row_candidates_avx512(d, upmax, upmin, downmax, downmin, w, pre, out);
#endif
    return row_candidates_portable(d, upmax, upmin, downmax, downmin, w, pre, out);
}

}  // namespace sift
}  // namespace canonform::views
