// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/sift_features.h"

#include <opencv2/core.hpp>
#include <opencv2/core/hal/hal.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <vl/sift.h>
}

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <memory>
#include <string>

namespace canonform::views {

const std::vector<std::string>& sift_backend_names() {
    static const std::vector<std::string> names = {"opencv",      "opencv-half",    "vlfeat",
                                                   "opencv-fast", "opencv-octave0", "opencv-octave0-fine"};
    return names;
}

SiftBackend parse_sift_backend(const std::string& name) {
    const auto& names = sift_backend_names();
    std::string choices;
    for (size_t k = 0; k < names.size(); ++k) {
        if (names[k] == name) return static_cast<SiftBackend>(k);
        choices += (k ? ", " : "") + names[k];
    }
    throw InputError("SIFT: unknown backend '" + name + "' (" + choices + ").");
}

std::string sift_backend_name(SiftBackend backend) { return sift_backend_names().at(static_cast<size_t>(backend)); }

namespace {

void check_size(size_t have, int size, const char* unit) {
    if (size <= 0) throw InputError("SIFT: the image size must be positive (got " + std::to_string(size) + ").");
    const size_t expected = static_cast<size_t>(size) * static_cast<size_t>(size);
    if (have != expected)
        throw InputError("SIFT: the image buffer has " + std::to_string(have) + " " + unit + ", expected " +
                         std::to_string(expected) + " for a " + std::to_string(size) + " x " +
                         std::to_string(size) + " image.");
}

// VLFeat's SIFT at its defaults on a float image (values 0-255).
SiftFeatures vlfeat_sift(const std::vector<float>& image, int size) {
    std::unique_ptr<VlSiftFilt, void (*)(VlSiftFilt*)> f(vl_sift_new(size, size, -1, 3, 0), vl_sift_delete);
    if (!f) throw NumericalError("SIFT: VLFeat could not allocate its filter.");
    vl_sift_set_peak_thresh(f.get(), 0.0);
    vl_sift_set_edge_thresh(f.get(), 10.0);
    SiftFeatures out;
    std::vector<float> rows;  // n * 128
    float d[128];
    double angles[4];
    int err = vl_sift_process_first_octave(f.get(), image.data());
    while (err != VL_ERR_EOF) {
        vl_sift_detect(f.get());
        const VlSiftKeypoint* keys = vl_sift_get_keypoints(f.get());
        const int n = vl_sift_get_nkeypoints(f.get());
        for (int i = 0; i < n; ++i) {
            const int na = vl_sift_calc_keypoint_orientations(f.get(), angles, &keys[i]);
            for (int a = 0; a < na; ++a) {
                vl_sift_calc_keypoint_descriptor(f.get(), d, &keys[i], angles[a]);
                for (float v : d) rows.push_back(std::min(255.f, std::floor(512.f * v)));
                out.keypoints.push_back({keys[i].x, keys[i].y, keys[i].sigma, static_cast<float>(angles[a] * 57.29577951308232),
                                         keys[i].o});
            }
        }
        err = vl_sift_process_next_octave(f.get());
    }
    out.descriptors.resize(static_cast<Eigen::Index>(rows.size() / 128), 128);
    std::copy(rows.begin(), rows.end(), out.descriptors.data());
    return out;
}

// OpenCV packs a keypoint's octave into the low byte of KeyPoint::octave as a signed 8-bit value
// (the layer and sub-layer offset in the higher bytes).
int keypoint_octave(const cv::KeyPoint& k) { return static_cast<std::int8_t>(k.octave & 255); }

// Where OpenCV's keypoints are. With its doubled first octave (detection, and compute() when a
// keypoint has octave -1), OpenCV upsamples with half-pixel centres (doubled pixel j is image
// position j/2 - 0.25) but reports j/2: its positions are 0.25 pixel right of and below the
// feature. Without doubling (compute() of keypoints of octave >= 0) it reads a keypoint's position
// as the image position itself.
constexpr float kDoubledOffset = 0.25f;

// Layers of opencv-octave0-fine's extra octave (see sift_features()).
constexpr int kFineOctaveLayers = 2;

// OpenCV keypoints of the half view moved to the full view, as compute() without doubling reads
// them: half-view pixel i covers full pixels 2i and 2i + 1 (INTER_AREA), i.e. full = 2 h + 0.5;
// with the reported h = true h + 0.25 that is full = 2 h(reported). Size x 2; octave + 1 (the
// half view's octave -1, its doubled image, is the full view's octave 0).
void half_to_full(std::vector<cv::KeyPoint>& keypoints) {
    for (cv::KeyPoint& k : keypoints) {
        k.pt = cv::Point2f(2.f * k.pt.x, 2.f * k.pt.y);
        k.size *= 2.f;
        k.octave = (k.octave & ~255) | ((keypoint_octave(k) + 1) & 255);
    }
}

// Provenance: the detector and descriptor below are adapted from OpenCV 4.6's
// modules/features2d/src/sift.simd.hpp (Apache License 2.0, the licence of OpenCV >= 4.5; OpenCV's
// SIFT derives from Rob Hess's implementation), so that their keypoints and descriptors equal
// OpenCV's; the adaptation (octave-0 grid, one pyramid for both) is ours.
//
// opencv-octave0's detector: OpenCV 4.6's own DoG detector (sift.simd.hpp: findScaleSpaceExtrema,
// adjustLocalExtrema, calcOrientationHist, same constants, float arithmetic and keypoint packing)
// restricted to OpenCV's octaves >= 0, computed on the view itself instead of on OpenCV's doubled
// image. OpenCV's octave 0 is the nearest-neighbour half of its doubled (INTER_LINEAR, half-pixel
// centres) image: doubled pixel 2i samples the view at i - 1/4, i.e. 0.25 * I[i-1] + 0.75 * I[i]
// per axis. That 2-tap filter is what makes OpenCV's octave-0 keypoints: a first octave on the
// view with a symmetric base blur finds a third of them (2.9 vs 10.5 keypoint locations per view
// on the bench view; 9.3 with no base-blur allowance), with the filter 11.3. So `shifted` is the
// view resampled at i - 1/4 (both axes), the pyramid starts there at octave 0 with OpenCV's base
// blur from SIFT_INIT_SIGMA 0.5 to sigma, and positions are in the shifted image's pixels (a
// feature at shifted x is at view x - 1/4, the offset OpenCV's doubled positions carry too).
// With `descriptors`, also OpenCV's descriptors of the keypoints (calcDescriptors on the same
// pyramid, as OpenCV takes them from its octaves >= 0).
// OpenCV 4.6's calcSIFTDescriptor (d = 4, n = 8, SIFT_DESCR_SCL_FCTR 3, SIFT_DESCR_MAG_THR 0.2,
// SIFT_INT_DESCR_FCTR 512, values saturated to 0-255) for a keypoint at ptf (pixels of img) with
// orientation ori (degrees, OpenCV's 360 - angle) and scale scl, into dst (128 floats).
void sift_descriptor(const cv::Mat& img, cv::Point2f ptf, float ori, float scl, float* dst) {
    constexpr int d = 4, n = 8;
    const cv::Point pt(cvRound(ptf.x), cvRound(ptf.y));
    float cos_t = std::cos(ori * static_cast<float>(CV_PI / 180)), sin_t = std::sin(ori * static_cast<float>(CV_PI / 180));
    const float bins_per_rad = n / 360.f, exp_scale = -1.f / (d * d * 0.5f), hist_width = 3.f * scl;
    int radius = cvRound(hist_width * 1.4142135623730951f * (d + 1) * 0.5f);
    radius = std::min(radius, static_cast<int>(std::sqrt(double(img.cols) * img.cols + double(img.rows) * img.rows)));
    cos_t /= hist_width;
    sin_t /= hist_width;
    const int rows = img.rows, cols = img.cols;
    float hist[(d + 2) * (d + 2) * (n + 2)] = {};
    // As OpenCV: the window's samples first, then exp, atan and magnitude over all of them at once
    // (cv::hal's vectorised functions), then the tri-linear binning.
    const size_t window = static_cast<size_t>(2 * radius + 1) * static_cast<size_t>(2 * radius + 1);
    thread_local std::vector<float> buffer;
    buffer.resize(window * 7);
    float *X = buffer.data(), *Y = X + window, *Ori = Y + window, *Mag = Ori + window, *W = Mag + window,
          *RBin = W + window, *CBin = RBin + window;
    int samples = 0;
    for (int i = -radius; i <= radius; ++i)
        for (int j = -radius; j <= radius; ++j) {
            const float c_rot = static_cast<float>(j) * cos_t - static_cast<float>(i) * sin_t;
            const float r_rot = static_cast<float>(j) * sin_t + static_cast<float>(i) * cos_t;
            const float rbin = r_rot + d / 2 - 0.5f, cbin = c_rot + d / 2 - 0.5f;
            const int r = pt.y + i, c = pt.x + j;
            if (!(rbin > -1 && rbin < d && cbin > -1 && cbin < d && r > 0 && r < rows - 1 && c > 0 && c < cols - 1)) continue;
            X[samples] = img.at<float>(r, c + 1) - img.at<float>(r, c - 1);
            Y[samples] = img.at<float>(r - 1, c) - img.at<float>(r + 1, c);
            RBin[samples] = rbin;
            CBin[samples] = cbin;
            W[samples] = (c_rot * c_rot + r_rot * r_rot) * exp_scale;
            ++samples;
        }
    cv::hal::fastAtan2(Y, X, Ori, samples, true);
    cv::hal::magnitude32f(X, Y, Mag, samples);
    cv::hal::exp32f(W, W, samples);
    for (int k = 0; k < samples; ++k) {
        float rbin = RBin[k], cbin = CBin[k];
        float obin = (Ori[k] - ori) * bins_per_rad;
        const float mag = Mag[k] * W[k];
        const int r0 = cvFloor(rbin), c0 = cvFloor(cbin);
        int o0 = cvFloor(obin);
        rbin -= static_cast<float>(r0);
        cbin -= static_cast<float>(c0);
        obin -= static_cast<float>(o0);
        if (o0 < 0) o0 += n;
        if (o0 >= n) o0 -= n;
        // tri-linear interpolation
        const float v_r1 = mag * rbin, v_r0 = mag - v_r1;
        const float v_rc11 = v_r1 * cbin, v_rc10 = v_r1 - v_rc11, v_rc01 = v_r0 * cbin, v_rc00 = v_r0 - v_rc01;
        const float v_rco111 = v_rc11 * obin, v_rco110 = v_rc11 - v_rco111, v_rco101 = v_rc10 * obin,
                    v_rco100 = v_rc10 - v_rco101, v_rco011 = v_rc01 * obin, v_rco010 = v_rc01 - v_rco011,
                    v_rco001 = v_rc00 * obin, v_rco000 = v_rc00 - v_rco001;
        const int idx = ((r0 + 1) * (d + 2) + c0 + 1) * (n + 2) + o0;
        hist[idx] += v_rco000;
        hist[idx + 1] += v_rco001;
        hist[idx + (n + 2)] += v_rco010;
        hist[idx + (n + 3)] += v_rco011;
        hist[idx + (d + 2) * (n + 2)] += v_rco100;
        hist[idx + (d + 2) * (n + 2) + 1] += v_rco101;
        hist[idx + (d + 3) * (n + 2)] += v_rco110;
        hist[idx + (d + 3) * (n + 2) + 1] += v_rco111;
    }
    for (int i = 0; i < d; ++i)  // the orientation histograms are circular
        for (int j = 0; j < d; ++j) {
            const int idx = ((i + 1) * (d + 2) + (j + 1)) * (n + 2);
            hist[idx] += hist[idx + n];
            hist[idx + 1] += hist[idx + n + 1];
            for (int k = 0; k < n; ++k) dst[(i * d + j) * n + k] = hist[idx + k];
        }
    constexpr int len = d * d * n;
    float nrm2 = 0;
    for (int k = 0; k < len; ++k) nrm2 += dst[k] * dst[k];
    const float thr = std::sqrt(nrm2) * 0.2f;
    nrm2 = 0;
    for (int k = 0; k < len; ++k) {
        dst[k] = std::min(dst[k], thr);
        nrm2 += dst[k] * dst[k];
    }
    nrm2 = 512.f / std::max(std::sqrt(nrm2), FLT_EPSILON);
    for (int k = 0; k < len; ++k) dst[k] = static_cast<float>(cv::saturate_cast<uchar>(dst[k] * nrm2));
}

// An angle of 360 degrees (within FLT_EPSILON) as 0, as OpenCV writes orientations.
float zero_for_360(float degrees) { return std::abs(degrees - 360.f) < FLT_EPSILON ? 0.f : degrees; }

// At most max_octaves octaves (opencv-octave0-fine's extra octave is one).
std::vector<cv::KeyPoint> dog_keypoints(const cv::Mat& shifted, const SiftOptions& o, cv::Mat* descriptors = nullptr,
                                        int max_octaves = INT_MAX) {
    const int L = o.octave_layers;
    const double k = std::pow(2.0, 1.0 / L);
    std::vector<double> blur(static_cast<size_t>(L + 3));
    blur[0] = o.sigma;
    for (int i = 1; i < L + 3; ++i) {
        const double prev = std::pow(k, i - 1) * o.sigma, total = prev * k;
        blur[static_cast<size_t>(i)] = std::sqrt(total * total - prev * prev);
    }
    const int octaves =
        std::min(max_octaves, std::max(1, static_cast<int>(std::lround(std::log2(std::min(shifted.rows, shifted.cols)))) - 2));
    std::vector<std::vector<cv::Mat>> g(static_cast<size_t>(octaves)), d(static_cast<size_t>(octaves));
    const double base_blur = std::sqrt(std::max(o.sigma * o.sigma - 0.25, 0.01));  // SIFT_INIT_SIGMA 0.5
    for (int oc = 0; oc < octaves; ++oc) {
        auto& G = g[static_cast<size_t>(oc)];
        G.resize(static_cast<size_t>(L + 3));
        if (oc == 0) {
            cv::GaussianBlur(shifted, G[0], cv::Size(), base_blur, base_blur);
        } else {
            const cv::Mat& src = g[static_cast<size_t>(oc - 1)][static_cast<size_t>(L)];
            cv::resize(src, G[0], cv::Size(src.cols / 2, src.rows / 2), 0, 0, cv::INTER_NEAREST);
        }
        for (int i = 1; i < L + 3; ++i)
            cv::GaussianBlur(G[static_cast<size_t>(i - 1)], G[static_cast<size_t>(i)], cv::Size(), blur[static_cast<size_t>(i)],
                             blur[static_cast<size_t>(i)]);
        auto& D = d[static_cast<size_t>(oc)];
        D.resize(static_cast<size_t>(L + 2));
        for (int i = 0; i < L + 2; ++i) cv::subtract(G[static_cast<size_t>(i + 1)], G[static_cast<size_t>(i)], D[static_cast<size_t>(i)]);
    }
    constexpr int border = 5;                 // SIFT_IMG_BORDER
    constexpr int max_steps = 5;              // SIFT_MAX_INTERP_STEPS
    constexpr float img_scale = 1.f / 255.f;  // derivatives in units of the [0, 1] image
    const float threshold = static_cast<float>(std::floor(0.5 * o.contrast_threshold / L * 255.0));
    const float contrast_threshold = static_cast<float>(o.contrast_threshold);
    const float edge = static_cast<float>(o.edge_threshold);
    const float sigma = static_cast<float>(o.sigma);
    std::vector<cv::KeyPoint> out;
    for (int oc = 0; oc < octaves; ++oc) {
        const auto& D = d[static_cast<size_t>(oc)];
        const auto& G = g[static_cast<size_t>(oc)];
        const int rows = D[0].rows, cols = D[0].cols;
        if (rows <= 2 * border || cols <= 2 * border) break;
        // Extrema: >= (maximum) or <= (minimum) all 26 neighbours, as OpenCV; via the 3 x 3 maxima
        // and minima of each DoG layer (v >= every neighbour iff v >= the 3 x 3 maxima of the layers
        // below, at and above), tested branch-free a row at a time.
        std::vector<cv::Mat> hi(D.size()), lo(D.size());
        const cv::Mat box = cv::Mat::ones(3, 3, CV_8U);
        for (size_t j = 0; j < D.size(); ++j) {
            cv::dilate(D[j], hi[j], box);
            cv::erode(D[j], lo[j], box);
        }
        std::vector<std::uint8_t> candidate(static_cast<size_t>(cols));
        for (int i = 1; i <= L; ++i)
            for (int r = border; r < rows - border; ++r) {
                const auto at_row = [r](const std::vector<cv::Mat>& m, int j) { return m[static_cast<size_t>(j)].ptr<float>(r); };
                const float *v = at_row(D, i), *h0 = at_row(hi, i - 1), *h1 = at_row(hi, i), *h2 = at_row(hi, i + 1),
                            *l0 = at_row(lo, i - 1), *l1 = at_row(lo, i), *l2 = at_row(lo, i + 1);
                for (int c = border; c < cols - border; ++c) {
                    const float x = v[c];
                    const bool maximum = (x > threshold) & (x >= h0[c]) & (x >= h1[c]) & (x >= h2[c]);
                    const bool minimum = (x < -threshold) & (x <= l0[c]) & (x <= l1[c]) & (x <= l2[c]);
                    candidate[static_cast<size_t>(c)] = static_cast<std::uint8_t>(maximum | minimum);
                }
                for (int c = border; c < cols - border; ++c) {
                    if (!candidate[static_cast<size_t>(c)]) continue;
                    // adjustLocalExtrema: quadratic refinement (Lowe Sec. 4), up to 5 moves.
                    int li = i, rr = r, cc = c;
                    float xi = 0, xr = 0, xc = 0;
                    auto at = [&D](int layer, int y, int x) { return D[static_cast<size_t>(layer)].at<float>(y, x); };
                    auto gradient = [&](int l, int y, int x) {
                        return cv::Vec3f((at(l, y, x + 1) - at(l, y, x - 1)) * 0.5f * img_scale,
                                         (at(l, y + 1, x) - at(l, y - 1, x)) * 0.5f * img_scale,
                                         (at(l + 1, y, x) - at(l - 1, y, x)) * 0.5f * img_scale);
                    };
                    // The in-layer second derivatives (dxx, dyy, dxy): the refinement's and the edge test's.
                    auto hessian_xy = [&](int l, int y, int x) {
                        const float v2 = at(l, y, x) * 2;
                        return cv::Vec3f((at(l, y, x + 1) + at(l, y, x - 1) - v2) * img_scale,
                                         (at(l, y + 1, x) + at(l, y - 1, x) - v2) * img_scale,
                                         (at(l, y + 1, x + 1) - at(l, y + 1, x - 1) - at(l, y - 1, x + 1) + at(l, y - 1, x - 1)) *
                                             0.25f * img_scale);
                    };
                    int step = 0;
                    for (; step < max_steps; ++step) {
                        const cv::Vec3f dD = gradient(li, rr, cc);
                        const cv::Vec3f hxy = hessian_xy(li, rr, cc);
                        const float dxx = hxy[0], dyy = hxy[1], dxy = hxy[2];
                        const float dss = (at(li + 1, rr, cc) + at(li - 1, rr, cc) - at(li, rr, cc) * 2) * img_scale;
                        const float dxs = (at(li + 1, rr, cc + 1) - at(li + 1, rr, cc - 1) - at(li - 1, rr, cc + 1) +
                                           at(li - 1, rr, cc - 1)) * 0.25f * img_scale;
                        const float dys = (at(li + 1, rr + 1, cc) - at(li + 1, rr - 1, cc) - at(li - 1, rr + 1, cc) +
                                           at(li - 1, rr - 1, cc)) * 0.25f * img_scale;
                        const cv::Matx33f H(dxx, dxy, dxs, dxy, dyy, dys, dxs, dys, dss);
                        const cv::Vec3f X = H.solve(dD, cv::DECOMP_LU);
                        xi = -X[2], xr = -X[1], xc = -X[0];
                        if (std::abs(xi) < 0.5f && std::abs(xr) < 0.5f && std::abs(xc) < 0.5f) break;
                        constexpr float huge = static_cast<float>(INT_MAX / 3);
                        if (!(std::abs(xi) <= huge && std::abs(xr) <= huge && std::abs(xc) <= huge)) {
                            step = max_steps;
                            break;
                        }
                        cc += cvRound(xc);
                        rr += cvRound(xr);
                        li += cvRound(xi);
                        if (li < 1 || li > L || cc < border || cc >= cols - border || rr < border || rr >= rows - border) {
                            step = max_steps;
                            break;
                        }
                    }
                    if (step >= max_steps) continue;
                    const float contrast = at(li, rr, cc) * img_scale + gradient(li, rr, cc).dot(cv::Vec3f(xc, xr, xi)) * 0.5f;
                    if (std::abs(contrast) * static_cast<float>(L) < contrast_threshold) continue;
                    const cv::Vec3f hxy = hessian_xy(li, rr, cc);
                    const float tr = hxy[0] + hxy[1], det = hxy[0] * hxy[1] - hxy[2] * hxy[2];
                    if (det <= 0 || tr * tr * edge >= (edge + 1) * (edge + 1) * det) continue;
                    cv::KeyPoint kp;
                    const float unit = static_cast<float>(1 << oc);
                    kp.pt = cv::Point2f((static_cast<float>(cc) + xc) * unit, (static_cast<float>(rr) + xr) * unit);
                    kp.octave = oc + (li << 8) + (cvRound((xi + 0.5f) * 255) << 16);
                    kp.size = sigma * std::pow(2.f, (static_cast<float>(li) + xi) / static_cast<float>(L)) * unit * 2;
                    kp.response = std::abs(contrast);
                    // calcOrientationHist (Lowe Sec. 5): 36 bins on the keypoint's Gaussian layer.
                    const cv::Mat& img = G[static_cast<size_t>(li)];
                    constexpr int bins = 36;
                    const float scl = kp.size * 0.5f / unit;
                    const int radius = cvRound(4.5f * scl);  // SIFT_ORI_RADIUS = 3 * SIFT_ORI_SIG_FCTR
                    const float expf_scale = -1.f / (2.f * (1.5f * scl) * (1.5f * scl));
                    float hist[bins] = {};
                    const size_t window = static_cast<size_t>(2 * radius + 1) * static_cast<size_t>(2 * radius + 1);
                    thread_local std::vector<float> buffer;
                    buffer.resize(window * 5);
                    float *X = buffer.data(), *Y = X + window, *W = Y + window, *Ori = W + window, *Mag = Ori + window;
                    int len = 0;
                    for (int dy = -radius; dy <= radius; ++dy) {
                        const int y = rr + dy;
                        if (y <= 0 || y >= rows - 1) continue;
                        for (int dx = -radius; dx <= radius; ++dx) {
                            const int x = cc + dx;
                            if (x <= 0 || x >= cols - 1) continue;
                            X[len] = img.at<float>(y, x + 1) - img.at<float>(y, x - 1);
                            Y[len] = img.at<float>(y - 1, x) - img.at<float>(y + 1, x);
                            W[len] = static_cast<float>(dx * dx + dy * dy) * expf_scale;
                            ++len;
                        }
                    }
                    // As OpenCV: exp, atan and magnitude over the whole window (cv::hal, vectorised).
                    cv::hal::exp32f(W, W, len);
                    cv::hal::fastAtan2(Y, X, Ori, len, true);
                    cv::hal::magnitude32f(X, Y, Mag, len);
                    for (int k = 0; k < len; ++k) {
                        int bin = cvRound((bins / 360.f) * Ori[k]);
                        if (bin >= bins) bin -= bins;
                        if (bin < 0) bin += bins;
                        hist[bin] += W[k] * Mag[k];
                    }
                    float smooth[bins];
                    for (int b = 0; b < bins; ++b)
                        smooth[b] = (hist[(b + bins - 2) % bins] + hist[(b + 2) % bins]) * (1.f / 16.f) +
                                    (hist[(b + bins - 1) % bins] + hist[(b + 1) % bins]) * (4.f / 16.f) + hist[b] * (6.f / 16.f);
                    const float peak = *std::max_element(smooth, smooth + bins) * 0.8f;  // SIFT_ORI_PEAK_RATIO
                    for (int b = 0; b < bins; ++b) {
                        const float left = smooth[(b + bins - 1) % bins], right = smooth[(b + 1) % bins];
                        if (!(smooth[b] > left && smooth[b] > right && smooth[b] >= peak)) continue;
                        float bin = static_cast<float>(b) + 0.5f * (left - right) / (left - 2 * smooth[b] + right);
                        bin = bin < 0 ? bins + bin : bin >= bins ? bin - bins : bin;
                        kp.angle = zero_for_360(360.f - (360.f / bins) * bin);
                        out.push_back(kp);
                    }
                }
            }
    }
    if (descriptors) {  // calcDescriptors: on the keypoint's Gaussian layer, angle 360 - kp.angle
        descriptors->create(static_cast<int>(out.size()), 128, CV_32F);
        for (size_t i = 0; i < out.size(); ++i) {
            const cv::KeyPoint& kp = out[i];
            const int oc = kp.octave & 255, layer = (kp.octave >> 8) & 255;
            const float scale = 1.f / static_cast<float>(1 << oc);
            sift_descriptor(g[static_cast<size_t>(oc)][static_cast<size_t>(layer)], kp.pt * scale, zero_for_360(360.f - kp.angle), kp.size * scale * 0.5f,
                            descriptors->ptr<float>(static_cast<int>(i)));
        }
    }
    return out;
}

}  // namespace

SiftFeatures depth_sift_features(const std::vector<float>& depth, int size, const SiftOptions& options) {
    check_size(depth.size(), size, "values");
    if (options.backend != SiftBackend::VLFeat) {
        std::vector<std::uint8_t> g(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            g[i] = static_cast<std::uint8_t>(std::round(255.0 * std::clamp(static_cast<double>(depth[i]), 0.0, 1.0)));
        return sift_features(g, size, options);
    }
    bool constant = true;
    for (size_t k = 1; k < depth.size() && constant; ++k) constant = depth[k] == depth[0];
    if (constant) return {};
    std::vector<float> image(depth.size());
    for (size_t i = 0; i < depth.size(); ++i) image[i] = 255.f * std::clamp(depth[i], 0.f, 1.f);
    return vlfeat_sift(image, size);
}

SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size, const SiftOptions& options) {
    return depth_sift_features(depth, size, options).descriptors;
}

SiftFeatures sift_features(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    check_size(gray.size(), size, "bytes");
    if (!(options.contrast_threshold >= 0) || !std::isfinite(options.contrast_threshold))
        throw InputError("SIFT: contrast_threshold must be a finite value >= 0.");
    if (!(options.edge_threshold > 0) || !std::isfinite(options.edge_threshold))
        throw InputError("SIFT: edge_threshold must be a finite value > 0.");
    if (!(options.sigma > 0) || !std::isfinite(options.sigma)) throw InputError("SIFT: sigma must be > 0.");
    if (options.octave_layers < 1) throw InputError("SIFT: octave_layers must be >= 1.");
    if (options.max_features < 0) throw InputError("SIFT: max_features must be >= 0 (0 = all).");

    // A constant image has no DoG extrema; skip OpenCV entirely (and guarantee 0 rows).
    bool constant = true;
    for (size_t k = 1; k < gray.size() && constant; ++k) constant = gray[k] == gray[0];
    if (constant) return {};

    if (options.backend == SiftBackend::VLFeat) {
        std::vector<float> image(gray.begin(), gray.end());
        return vlfeat_sift(image, size);
    }
    cv::Mat image(size, size, CV_8UC1, const_cast<std::uint8_t*>(gray.data()));
    cv::Ptr<cv::SIFT> sift = cv::SIFT::create(options.max_features, options.octave_layers,
                                              options.contrast_threshold, options.edge_threshold, options.sigma);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    if (options.backend == SiftBackend::OpenCV) {
        sift->detectAndCompute(image, cv::noArray(), keypoints, descriptors);
    } else if (options.backend == SiftBackend::OpenCVOctave0 || options.backend == SiftBackend::OpenCVOctave0Fine) {
        // Detection and descriptors on the view resampled at i - 1/4 on both axes (OpenCV's
        // octave-0 grid, see dog_keypoints), in one pyramid; positions moved to the view.
        cv::Mat view, shifted;
        image.convertTo(view, CV_32F);
        const cv::Mat tap = (cv::Mat_<float>(1, 3) << 0.25f, 0.75f, 0.f);
        cv::sepFilter2D(view, shifted, CV_32F, tap, tap.t(), cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        keypoints = dog_keypoints(shifted, options, &descriptors);
        for (cv::KeyPoint& k : keypoints) k.pt -= cv::Point2f(kDoubledOffset, kDoubledOffset);  // to the view
        if (options.backend == SiftBackend::OpenCVOctave0Fine) {
            // The approximate octave -1: one octave on the view itself (not resampled, not
            // doubled) from sigma / 2, the scale of OpenCV's doubled octave, with 2 layers (3 pick
            // up the 8-bit quantisation: ten times opencv's octave -1 keypoints). Its keypoints are
            // reported at octave -1, before the others (as OpenCV orders them).
            SiftOptions fine = options;
            fine.sigma = options.sigma * 0.5;
            fine.octave_layers = kFineOctaveLayers;
            cv::Mat fine_descriptors;
            std::vector<cv::KeyPoint> extra = dog_keypoints(view, fine, &fine_descriptors, 1);
            for (cv::KeyPoint& k : extra) k.octave = (k.octave & ~255) | 255;  // octave -1 in OpenCV's packing
            if (!extra.empty()) {
                keypoints.insert(keypoints.begin(), extra.begin(), extra.end());
                if (descriptors.empty()) descriptors = fine_descriptors;
                else cv::vconcat(fine_descriptors, descriptors, descriptors);
            }
        }
    } else {
        cv::Mat half;
        cv::resize(image, half, cv::Size(std::max(1, size / 2), std::max(1, size / 2)), 0, 0, cv::INTER_AREA);
        if (options.backend == SiftBackend::OpenCVHalf) {
            sift->detectAndCompute(half, cv::noArray(), keypoints, descriptors);
            half_to_full(keypoints);  // reported in the view's coordinates
        } else {
            // opencv-fast: the half view's keypoints (and orientations), then descriptors of the
            // full view; every keypoint has octave >= 0 there, so cv::SIFT::compute builds its
            // pyramid from the view itself (first octave 0) instead of doubling it.
            sift->detect(half, keypoints);
            half_to_full(keypoints);
            if (!keypoints.empty()) sift->compute(image, keypoints, descriptors);
        }
    }
    SiftFeatures out;
    if (descriptors.empty()) return out;
    if (descriptors.cols != 128 || descriptors.type() != CV_32F || descriptors.rows != static_cast<int>(keypoints.size()))
        throw NumericalError("SIFT: OpenCV returned descriptors of an unexpected shape or type.");
    out.descriptors.resize(descriptors.rows, 128);
    for (int r = 0; r < descriptors.rows; ++r) {
        const float* src = descriptors.ptr<float>(r);
        for (int c = 0; c < 128; ++c) out.descriptors(r, c) = src[c];
    }
    out.keypoints.reserve(keypoints.size());
    const float offset = options.backend == SiftBackend::OpenCV ? kDoubledOffset : 0.f;  // to the feature's position
    for (const cv::KeyPoint& k : keypoints)
        out.keypoints.push_back({k.pt.x - offset, k.pt.y - offset, k.size, k.angle, keypoint_octave(k)});
    return out;
}

SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    return sift_features(gray, size, options).descriptors;
}

}  // namespace canonform::views
