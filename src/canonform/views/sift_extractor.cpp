// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/sift_extractor.h"

#include "canonform/numerics/portable_math.h"
#include "canonform/views/sift_simd.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace canonform::views {
namespace sift {

namespace {

constexpr int kOrientationBins = 36;       // Lowe Sec. 5
constexpr double kOrientationSigma = 1.5;  // sigma_w / sigma, Lowe Sec. 5
constexpr double kOrientationRadius = 3;   // window radius / sigma_w (ours)
constexpr double kPeakRatio = 0.8;         // Lowe Sec. 5
constexpr int kMaxFits = 5;                // sub-pixel fits per extremum (ours)
constexpr double kPreTest = 0.5;           // |D| >= kPreTest * t before the fit (ours)
constexpr int kMinOctaveSize = 8;          // octaves while the view is at least this wide at the octave
constexpr int kFineLayers = 2;             // DoG images searched in the approximate octave -1 (ours)
constexpr int kOrientationSmoothing = 2;   // passes of [1 2 1] / 4 over the orientation histogram (ours)

}  // namespace

Rect window(const Plane& L, const Candidate& c, double radius) {
    const Rect inner = L.support.grown(-1);
    return {std::max(inner.x0, c.X + static_cast<int>(std::ceil(c.fx - radius))),
            std::max(inner.y0, c.Y + static_cast<int>(std::ceil(c.fy - radius))),
            std::min(inner.x1 - 1, c.X + static_cast<int>(std::floor(c.fx + radius))),
            std::min(inner.y1 - 1, c.Y + static_cast<int>(std::floor(c.fy + radius)))};
}

int sample_step(float sigma) {
    return std::max(1, static_cast<int>(kBinWidth * double(sigma) / 4.0 + 0.5));
}

Extractor::Extractor(const float* image, int size, const Rect& box, const SiftOptions& o)
    : image_(image), size_(size), box_(box), o_(o) {
    st_.layers = o.octave_layers;
    st_.sigma0 = o.sigma;
    st_.k = numerics::portable_exp2(1.0 / o.octave_layers);
    st_.threshold = o.contrast_threshold / o.octave_layers;
    st_.edge_ratio = o.edge_threshold;
}

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
    ws_.shifted.resize(static_cast<size_t>(n) *
                       static_cast<size_t>(n));  // (read only over `box`, written below)
    // Per view row, along it h[x] = 0.75 row[x] + 0.25 row[x - 1] over the box's columns (a row or
    // column outside the view is 0), kept for the next row; then r[x] = 0.75 h_y[x] + 0.25 h_(y-1)[x].
    const int bw = box.width();
    const size_t cols = static_cast<size_t>(bw);
    std::vector<float>& buf = ws_.shift_rows;
    buf.resize(3 * cols + 1);
    float* line = buf.data();  // view columns box.x0 - 1 .. box.x1 - 1
    float* hu = line + cols + 1;
    float* hv = hu + cols;
    const int c0 = std::max(0, box.x0 - 1), c1 = std::min(size_, box.x1);  // the columns in the view
    const auto along = [&](int yy, float* h) {
        if (yy < 0 || yy >= size_) {
            std::fill(h, h + cols, 0.f);
            return;
        }
        const float* row = image_ + static_cast<size_t>(yy) * static_cast<size_t>(size_);
        std::fill(line, line + (cols + 1), 0.f);
        std::copy(row + c0, row + c1, line + (c0 - (box.x0 - 1)));
        for (size_t k = 0; k < cols; ++k) h[k] = 0.75f * line[k + 1] + 0.25f * line[k];
    };
    along(box.y0 - 1, hu);
    for (int y = box.y0; y < box.y1; ++y) {
        along(y, hv);
        float* r = ws_.shifted.data() + static_cast<size_t>(y) * static_cast<size_t>(n) + box.x0;
        for (size_t k = 0; k < cols; ++k) r[k] = 0.75f * hv[k] + 0.25f * hu[k];
        std::swap(hu, hv);
    }
    Plane grid;
    grid.data = ws_.shifted.data();
    grid.frame = {0, 0, n, n};
    grid.stride = n;
    grid.support = box;
    stack(grid, 1000, 0, 0.25f);
    // max_features: the strongest, in the order found.
    std::vector<size_t> keep(keys_.size());
    for (size_t i = 0; i < keep.size(); ++i) keep[i] = i;
    if (o_.max_features > 0 && keep.size() > static_cast<size_t>(o_.max_features)) {
        std::stable_sort(keep.begin(), keep.end(),
                         [&](size_t a, size_t b) { return keys_[a].response > keys_[b].response; });
        keep.resize(static_cast<size_t>(o_.max_features));
        std::sort(keep.begin(), keep.end());
    }
    out.keypoints.reserve(keep.size());
    out.descriptors.resize(static_cast<Eigen::Index>(keep.size()), 128);
    for (size_t r = 0; r < keep.size(); ++r) {
        out.keypoints.push_back(keys_[keep[r]]);
        std::memcpy(out.descriptors.row(static_cast<Eigen::Index>(r)).data(), desc_.data() + keep[r] * 128,
                    128 * sizeof(float));
    }
    return out;
}

// One scale space (step 1): from `input` (0 outside its support, blur input_blur), octaves 0 ..
// octaves - 1 of st_'s sampling; keypoints labelled octave `label` + o, at view position
// (octave-0 coordinate) - offset.
void Extractor::stack(const Plane& input, int octaves, int label, float offset) {
    std::vector<Plane> g;
    Rect obj = input.support;
    Plane prev_base;  // octave o's image j = layers (2 sigma0), for octave o + 1 (in the other bank)
    for (int o = 0; o < octaves && ((size_ >> o) >= kMinOctaveSize || o == 0); ++o) {
        gaussian_octave(o, obj, o == 0 ? input : prev_base, o_.input_blur, st_, ws_, g);
        octave(o, g, label + o, offset);
        // The next octave's base, and its object box (the pixels covering this one's, halved).
        prev_base = g[static_cast<size_t>(st_.layers)];
        const auto half_floor = [](int v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); };
        obj = {half_floor(obj.x0), half_floor(obj.y0), half_floor(obj.x1 - 1) + 1,
               half_floor(obj.y1 - 1) + 1};
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
        hits_.resize(static_cast<size_t>(w) + 16);  // (row_candidates may write 16 past)
        for (int y = region.y0; y < region.y1; ++y) {
            fill(slot_of(y + 1), y + 1);
            const float* d = ring_.data() + static_cast<size_t>(3 * slot_of(y)) * stride;
            const float* up = ring_.data() + static_cast<size_t>(3 * slot_of(y - 1)) * stride;
            const float* down = ring_.data() + static_cast<size_t>(3 * slot_of(y + 1)) * stride;
            const int found_here = row_candidates(d, up + stride, up + 2 * stride, down + stride,
                                                  down + 2 * stride, w, pre, hits_.data());
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
                c.sigma = static_cast<float>(st_.sigma0 * numerics::portable_exp2((J + off[2]) / st_.layers));
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
        if (!angles.empty()) describe_window(L, c, described_);
        for (double a : angles) {
            describe(L, c, a, described_, d.data());
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
bool Extractor::refine(const std::vector<Plane>& g, int jmin, int jmax, int& x, int& y, int& j, double off[3],
                       double& value) const {
    const auto D = [&](int jj, int xx, int yy) -> double {
        return double(g[static_cast<size_t>(jj + 1 - jmin)].at(xx, yy)) -
               double(g[static_cast<size_t>(jj - jmin)].at(xx, yy));
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
        const double hxy =
            0.25 * (D(j, x + 1, y + 1) - D(j, x - 1, y + 1) - D(j, x + 1, y - 1) + D(j, x - 1, y - 1));
        const double hxs =
            0.25 * (D(j + 1, x + 1, y) - D(j + 1, x - 1, y) - D(j - 1, x + 1, y) + D(j - 1, x - 1, y));
        const double hys =
            0.25 * (D(j + 1, x, y + 1) - D(j + 1, x, y - 1) - D(j - 1, x, y + 1) + D(j - 1, x, y - 1));
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
        const int mx = off[0] > 0.5    ? 1
                       : off[0] < -0.5 ? -1
                                       : 0,
                  my = off[1] > 0.5    ? 1
                       : off[1] < -0.5 ? -1
                                       : 0,
                  mj = off[2] > 0.5    ? 1
                       : off[2] < -0.5 ? -1
                                       : 0;
        const bool back = fit > 0 && x + mx == px && y + my == py && j + mj == pj &&
                          std::abs(off[0]) <= 0.6 && std::abs(off[1]) <= 0.6 && std::abs(off[2]) <= 0.6;
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

namespace {

// The orientation histogram's votes of the sampled pixels of the window [x0, x1] x [y0, y1] within
// the disk of squared radius r2 (the weights and squared offsets in `win`), eight samples at a time
// (lanes past x1 left out), each sample's two votes added in the samples' order.
CANONFORM_CLONES void orientation_votes(const Plane& L, const Candidate& c, int x0, int x1, int y0, int y1,
                                        int p, float r2, const WindowScratch& win, float* hist) {
    const float to_bin = static_cast<float>(kOrientationBins / (2 * kPi));
    const v8i lanes = v8i{0, 1, 2, 3, 4, 5, 6, 7} * p;
    alignas(32) float wv[8], bv[8];
    for (int y = align_up(y0, c.Y, p); y <= y1; y += p) {
        const float* up = L.row(y - 1);
        const float* mid = L.row(y);
        const float* down = L.row(y + 1);
        const float wyy = win.wy[static_cast<size_t>(y - y0)], dyy = win.dy2[static_cast<size_t>(y - y0)];
        for (int x = align_up(x0, c.X, p); x <= x1; x += 8 * p) {
            // Eight samples at once: weight m * w, bin position.
            const size_t i = static_cast<size_t>(x - x0);
            const int last = std::min(7, (x1 - x) / p);
            v8f gx, gy, m;
            gradients8(up, mid, down, x, p, last, gx, gy, m);
            const v8i in = (load8s(win.dx2.data() + i, p, last) + splat8(dyy) <= splat8(r2)) &
                           (m > splat8(0.f)) & (lanes <= splat8i(x1 - x));
            if (!mask8(in)) continue;
            const v8f wsel = m * (load8s(win.wx.data() + i, p, last) * splat8(wyy));
            store8(wv, in ? wsel : splat8(0.f));
            store8(bv, approximate_angle_0_to_2pi_lanes(gy, gx) * splat8(to_bin));
            for (int q = 0; q < 8; ++q) {
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
}

}  // namespace

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
    window_.wx.resize(nx + 16);
    window_.dx2.resize(nx + 16);
    window_.wy.resize(ny);
    window_.dy2.resize(ny);
    const double inv = -1.0 / (2.0 * sw * sw);
    // Only the sampled columns and rows (every p-th, aligned on the keypoint's sample) are read.
    const int p = sample_step(c.sigma);
    const size_t sx = static_cast<size_t>(align_up(x0, c.X, p) - x0),
                 sy = static_cast<size_t>(align_up(y0, c.Y, p) - y0), step = static_cast<size_t>(p);
    // (weights for the window's columns only; wx and dx2 have 16 more floats, which a block of
    // eight samples with p = 1 may read for lanes past x1: those lanes are left out)
    sampled_weights(x0, c.X, c.fx, sx, nx, step, inv, window_.wx.data(), window_.dx2.data());
    sampled_weights(y0, c.Y, c.fy, sy, ny, step, inv, window_.wy.data(), window_.dy2.data());
    const float r2 = static_cast<float>(radius * radius);
    float hist[kOrientationBins] = {};
    orientation_votes(L, c, x0, x1, y0, y1, p, r2, window_, hist);
    // Smoothed by a Gaussian of one bin (two passes of the circular [1 2 1] / 4).
    for (int pass = 0; pass < kOrientationSmoothing; ++pass) {
        float smooth[kOrientationBins];
        for (int i = 0; i < kOrientationBins; ++i)
            smooth[i] = 0.25f * (hist[(i + kOrientationBins - 1) % kOrientationBins] +
                                 hist[(i + 1) % kOrientationBins]) +
                        0.5f * hist[i];
        std::copy(smooth, smooth + kOrientationBins, hist);
    }
    float top = 0;
    for (float h : hist) top = std::max(top, h);
    if (!(top > 0.f)) return;
    for (int i = 0; i < kOrientationBins; ++i) {
        const float l = hist[(i + kOrientationBins - 1) % kOrientationBins], h = hist[i],
                    r = hist[(i + 1) % kOrientationBins];
        if (!(h > l && h > r && h >= static_cast<float>(kPeakRatio) * top)) continue;
        const double delta = 0.5 * (double(l) - double(r)) / (double(l) - 2.0 * double(h) + double(r));
        double a = (i + delta) * (2 * kPi / kOrientationBins);
        if (a < 0) a += 2 * kPi;
        if (a >= 2 * kPi) a -= 2 * kPi;
        angles.push_back(a);
    }
}

}  // namespace sift
}  // namespace canonform::views
