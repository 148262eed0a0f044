// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/sift_extractor.h"

#include "canonform/numerics/portable_math.h"
#include "canonform/views/sift_simd.h"

#include <algorithm>
#include <cmath>

namespace canonform::views {
namespace sift {

namespace {

constexpr float kClip = 0.2f;  // Lowe Sec. 6.1

}  // namespace

namespace {

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

}  // namespace

void describe_window(const Plane& L, const Candidate& k, WindowScratch& scratch) {
    const double w = kBinWidth * k.sigma;             // spatial bin width (octave pixels)
    const double half = (kGrid / 2.0 + 0.5) * w;      // half the grid plus half a bin
    const double radius = half * 1.4142135623730951;  // the rotated square's circumradius
    scratch.win = window(L, k, radius);
    const int x0 = scratch.win.x0, x1 = scratch.win.x1, y0 = scratch.win.y0, y1 = scratch.win.y1;
    if (x0 > x1 || y0 > y1) return;
    const size_t nx = static_cast<size_t>(x1 - x0 + 1), ny = static_cast<size_t>(y1 - y0 + 1);
    scratch.wx.resize(nx + 16);
    scratch.wy.resize(ny);
    const double sigma_w = 0.5 * kGrid * w;  // half the grid's width (Lowe)
    const double inv = -1.0 / (2.0 * sigma_w * sigma_w);
    // Only the sampled columns and rows (every p-th, aligned on the keypoint's sample) are read.
    const int p = sample_step(k.sigma);
    const size_t sx = static_cast<size_t>(align_up(x0, k.X, p) - x0),
                 sy = static_cast<size_t>(align_up(y0, k.Y, p) - y0), step = static_cast<size_t>(p);
    // (weights for the window's columns only; wx has 16 more floats, which a block of eight
    // samples with p = 1 may read for lanes past the window: those lanes are left out)
    sampled_weights(x0, k.X, k.fx, sx, nx, step, inv, scratch.wx.data());
    sampled_weights(y0, k.Y, k.fy, sy, ny, step, inv, scratch.wy.data());
}

void sampled_weights(int lo, int centre, float frac, size_t first, size_t count, size_t step, double inv,
                     float* w, float* d2) {
    // The exponentials in batches (numerics::portable_exp's vector lanes), the same bits.
    constexpr size_t kBatch = 64;
    double arg[kBatch], value[kBatch];
    for (size_t i = first; i < count;) {
        const size_t start = i;
        size_t m = 0;
        for (; i < count && m < kBatch; i += step, ++m) {
            const double d = double(lo + static_cast<int>(i) - centre) - double(frac);
            arg[m] = d * d * inv;
            if (d2) d2[i] = static_cast<float>(d * d);
        }
        numerics::portable_exp(arg, value, m);
        for (size_t k = 0, j = start; k < m; ++k, j += step) w[j] = static_cast<float>(value[k]);
    }
}

CANONFORM_CLONES void describe(const Plane& L, const Candidate& k, double angle, const WindowScratch& scratch,
                               float* out) {
    const double w = kBinWidth * k.sigma;  // spatial bin width (octave pixels)
    const int x0 = scratch.win.x0, x1 = scratch.win.x1, y0 = scratch.win.y0, y1 = scratch.win.y1;
    // Histogram with a border of one bin on every side (rows and columns -1..4) for the spread.
    constexpr int kSide = kGrid + 2;
    float hist[kSide * kSide * kAngles] = {};
    if (x0 <= x1 && y0 <= y1) {
        double sd, cd;
        numerics::portable_sincos(angle, sd, cd);
        const float c = static_cast<float>(cd / w), s = static_cast<float>(sd / w);
        const float centre = static_cast<float>(kGrid / 2.0 - 0.5);  // bin centres at 0..3
        const float to_bin = static_cast<float>(kAngles / (2 * kPi));
        const float a0 = static_cast<float>(angle);
        const float two_pi = static_cast<float>(2 * kPi);
        const int p = sample_step(k.sigma);
        for (int y = align_up(y0, k.Y, p); y <= y1; y += p) {
            const float* up = L.row(y - 1);
            const float* mid = L.row(y);
            const float* down = L.row(y + 1);
            const float dy = static_cast<float>(y - k.Y) - k.fy;
            const float wyy = scratch.wy[static_cast<size_t>(y - y0)];
            // Only the pixels near the rotated square (the test below decides).
            double lo = x0 - k.X, hi = x1 - k.X;
            narrow(c, double(s) * dy + centre, lo, hi);
            narrow(-double(s), double(c) * dy + centre, lo, hi);
            const int xa = align_up(k.X + static_cast<int>(lo), k.X, p), xb = k.X + static_cast<int>(hi);
            // Eight samples a step (x, x + p, ..., x + 7p), lanes past xb left out.
            const v8f lane = v8f{0.f, 1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f} * splat8(float(p));
            const v8i lanes = v8i{0, 1, 2, 3, 4, 5, 6, 7} * p;
            const v8f one = splat8(1.f), zero = splat8(0.f);
            for (int x = xa; x <= xb; x += 8 * p) {
                const size_t i = static_cast<size_t>(x - x0);
                const int last = std::min(7, (xb - x) / p);
                const v8f dx = (splat8(static_cast<float>(x - k.X)) + lane) - splat8(k.fx);
                const v8f col =
                    splat8(c) * dx + splat8(s * dy) + splat8(centre);  // along the keypoint's direction
                const v8f row =
                    splat8(-s) * dx + splat8(c * dy) + splat8(centre);  // 90 degrees clockwise from it
                v8f gx, gy, m;
                gradients8(up, mid, down, x, p, last, gx, gy, m);
                const v8i in = (col > splat8(-1.f)) & (col < splat8(float(kGrid))) & (row > splat8(-1.f)) &
                               (row < splat8(float(kGrid))) & (m > zero) & (lanes <= splat8i(xb - x));
                if (!mask8(in)) continue;
                v8f phi = splat8(a0) - approximate_angle_0_to_2pi_lanes(
                                           gy, gx);  // counted anticlockwise on screen (OpenCV's order)
                phi = phi < zero ? phi + splat8(two_pi) : phi;
                v8f ob = phi * splat8(to_bin);
                ob = ob >= splat8(float(kAngles)) ? ob - splat8(float(kAngles)) : ob;
                // Each lane's trilinear spread over bins r0, r0 + 1; c0, c0 + 1; o0, o1, formed for
                // eight lanes at once: wr = w (1 - fr) or w fr, wc = wr (1 - fc) or wr fc, then
                // wc (1 - fo) to o0 and wc fo to o1. The lanes inside the square are then added one
                // after another in the samples' order (a bin's sum, so its bits, depends on it).
                // Lanes outside are zeroed first (no out-of-range conversion to int).
                const v8f rs = in ? row : zero, cs = in ? col : zero, os = in ? ob : zero;
                const v8i r0 = floor8i(rs), c0 = floor8i(cs);
                v8i o0 = __builtin_convertvector(os, v8i);  // os >= 0: truncation is floor
                const v8f fr = rs - __builtin_convertvector(r0, v8f),
                          fc = cs - __builtin_convertvector(c0, v8f),
                          fo = os - __builtin_convertvector(o0, v8f);
                o0 = o0 >= splat8i(kAngles) ? o0 - splat8i(kAngles) : o0;
                const v8i o1 = o0 + 1 == splat8i(kAngles) ? splat8i(0) : o0 + 1;
                const v8f weight = m * (load8s(scratch.wx.data() + i, p, last) * splat8(wyy));
                const v8f wr0 = weight * (one - fr), wr1 = weight * fr;
                const v8f wc[4] = {wr0 * (one - fc), wr0 * fc, wr1 * (one - fc), wr1 * fc};
                const v8f go = one - fo;
                const v8i base = ((r0 + 1) * splat8i(kSide) + (c0 + 1)) * splat8i(kAngles);
                constexpr int kStep[4] = {0, kAngles, kSide * kAngles, (kSide + 1) * kAngles};
                v8f share0[4], share1[4];
                for (int b = 0; b < 4; ++b) {
                    share0[b] = wc[b] * go;
                    share1[b] = wc[b] * fo;
                }
                for (int q = 0; q < 8; ++q) {
                    if (!in[q]) continue;
                    float* h = hist + base[q];
                    const int bin0 = o0[q], bin1 = o1[q];
                    for (int b = 0; b < 4; ++b) {
                        h[kStep[b] + bin0] += share0[b][q];
                        h[kStep[b] + bin1] += share1[b][q];
                    }
                }
            }
        }
    }
    // The inner 4 x 4 bins; unit length, clipped at 0.2, unit length again (Lowe Sec. 6.1).
    float v[128];
    for (int r = 0; r < kGrid; ++r)
        for (int c = 0; c < kGrid; ++c)
            for (int a = 0; a < kAngles; ++a)
                v[(r * kGrid + c) * kAngles + a] = hist[((r + 1) * kSide + c + 1) * kAngles + a];
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

}  // namespace sift
}  // namespace canonform::views
