// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the SIFT extractor (private to the views area): extrema of the scale space, their
// sub-pixel fit, orientations and descriptors - steps 2-5 of sift_features.h, which says what each
// computes (Lowe Secs. 3.1, 4, 5 and 6.1).
#pragma once

#include "canonform/views/sift_features.h"
#include "canonform/views/sift_pyramid.h"

#include <vector>

namespace canonform::views {
namespace sift {

constexpr double kPi = 3.14159265358979323846;
constexpr int kGrid = 4;         // descriptor bins per side, Lowe Sec. 6.1
constexpr int kAngles = 8;       // descriptor orientation bins, Lowe Sec. 6.1
constexpr double kBinWidth = 3;  // descriptor bin width / sigma (VLFeat's documented magnification)

// An extremum kept by the fit, before its orientations.
struct Candidate {
    SiftKeypoint key;
    int layer = 0;         // Gaussian image j of the octave the keypoint is described in
    int X = 0, Y = 0;      // the sample (octave pixels)
    float fx = 0, fy = 0;  // the sub-pixel offset from it (|f| <= 0.5)
    float sigma = 0;       // scale in octave pixels
};

// The pixels of L within `radius` of the keypoint (a square, inside L's support less one pixel, so
// that central differences stay in it): [x0, x1] x [y0, y1].
Rect window(const Plane& L, const Candidate& c, double radius);

// Sampling of the orientation and descriptor windows: every p-th pixel of every p-th row (aligned
// on the keypoint's sample), p = max(1, round(w / 4)) for the descriptor's bin width w = 3 sigma:
// about 4 x 4 samples per bin (at least 3), as Lowe's 16 x 16 sample array over 4 x 4 bins (Sec. 6.1).
int sample_step(float sigma);

// The first value >= v with (value - origin) a multiple of p (p > 0).
inline int align_up(int v, int origin, int p) {
    const int d = v - origin;
    return origin + (d >= 0 ? (d + p - 1) / p : -((-d) / p)) * p;
}

// Gaussian weights exp(d^2 inv) of a window's sampled offsets along one axis: for i = first,
// first + step, ... below count, d = lo + i - centre - frac (in double: the pixel's offset from
// the keypoint) into w[i], and d^2 into d2[i] if d2 is given (the orientation and descriptor steps).
void sampled_weights(int lo, int centre, float frac, size_t first, size_t count, size_t step, double inv,
                     float* w, float* d2 = nullptr);

// Window weights of the orientation and descriptor steps, kept from one keypoint to the next (only
// the sampled columns and rows are computed). win: describe_window()'s window.
struct WindowScratch {
    std::vector<float> wx, wy, dx2, dy2;
    Rect win;
};

// The descriptor window of keypoint k in its Gaussian image L and its Gaussian weights, into scratch:
// the same for each of the keypoint's orientations (sift_descriptor.cpp).
void describe_window(const Plane& L, const Candidate& k, WindowScratch& scratch);

// Lowe Sec. 6.1: the 128 values of keypoint k with orientation `angle` (radians) in its Gaussian
// image L, with describe_window()'s window and weights of k (sift_descriptor.cpp).
void describe(const Plane& L, const Candidate& k, double angle, const WindowScratch& scratch, float* out);

// The canonform extractor of one view (image values in [0, 1], 0 outside `box`, its non-zero pixels).
class Extractor {
public:
    Extractor(const float* image, int size, const Rect& box, const SiftOptions& o);
    SiftFeatures run();

private:
    void stack(const Plane& input, int octaves, int label, float offset);
    void octave(int o, std::vector<Plane>& g, int label, float offset);
    bool refine(const std::vector<Plane>& g, int jmin, int jmax, int& x, int& y, int& j, double off[3],
                double& value) const;
    void orientations(const Plane& L, const Candidate& c, std::vector<double>& angles);

    const float* image_;
    int size_;
    Rect box_;  // the view's non-zero pixels
    SiftOptions o_;
    Settings st_;
    Workspace& ws_ = workspace();
    std::vector<SiftKeypoint> keys_;
    std::vector<float> ring_;  // the extremum scan's DoG rows
    std::vector<int> hits_;    // the candidates of a DoG row
    WindowScratch window_;     // the orientation window's weights
    WindowScratch described_;  // the descriptor window's weights
    std::vector<float> desc_;  // 128 per keypoint
};

}  // namespace sift
}  // namespace canonform::views
