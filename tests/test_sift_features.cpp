// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of sift_features.h: SIFT descriptors of depth views with each backend.
#include "canonform/views/sift_features.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

using namespace canonform;
using namespace canonform::views;

namespace {

/// The same keypoint to the bit: position, size, angle and OpenCV's packed octave.
void expect_same_keypoint(const SiftKeypoint& a, const SiftKeypoint& b) {
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.angle, b.angle);
    EXPECT_EQ(a.octave, b.octave);
}

// OpenCV's descriptor format: finite integer values 0-255, every row of L2 norm about 512.
void expect_opencv_descriptor_format(const SiftDescriptors& d) {
    EXPECT_TRUE(d.allFinite());
    EXPECT_GE(d.minCoeff(), 0.f);
    EXPECT_LE(d.maxCoeff(), 255.f);
    for (Eigen::Index r = 0; r < d.rows(); ++r) {
        EXPECT_NEAR(d.row(r).norm(), 512.f, 100.f);
        EXPECT_EQ(d.row(r), d.row(r).array().round().matrix());  // OpenCV's integer values
    }
}

// A synthetic 8-bit depth view: a sphere with nine Gaussian bumps (bumps = true) or a capsule
// stick figure; background 0.
std::vector<std::uint8_t> synthetic_depth(bool bumps, int n = 256) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(n) * n, 0);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const double x = (c + 0.5) / n * 2 - 1, y = (r + 0.5) / n * 2 - 1;
            double z = -2;
            if (bumps) {
                const double q = 0.64 - x * x - y * y;
                if (q > 0) {
                    z = std::sqrt(q);
                    for (int k = 0; k < 9; ++k) {
                        const double bx = -0.45 + 0.45 * (k % 3), by = -0.45 + 0.45 * (k / 3);
                        z += 0.15 * std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / 0.01);
                    }
                }
            } else {
                auto cap = [&](double ax, double ay, double bx, double by, double rad, double base) {
                    const double dx = bx - ax, dy = by - ay;
                    const double t = std::clamp(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
                    const double px = ax + t * dx - x, py = ay + t * dy - y, q = rad * rad - px * px - py * py;
                    if (q > 0) z = std::max(z, base + std::sqrt(q));
                };
                cap(0, -0.35, 0, 0.2, 0.17, 0);
                cap(0, -0.62, 0, -0.6, 0.12, 0.02);
                cap(-0.12, -0.3, -0.6, -0.05, 0.06, 0.05);
                cap(0.12, -0.3, 0.55, -0.55, 0.06, 0.05);
                cap(-0.08, 0.2, -0.3, 0.9, 0.08, 0);
                cap(0.08, 0.2, 0.25, 0.9, 0.08, -0.05);
            }
            if (z > -1.5)
                img[static_cast<std::size_t>(r) * n + c] =
                    static_cast<std::uint8_t>(std::clamp(1.0 + 254.0 * (z + 1) / 2, 1.0, 255.0));
        }
    return img;
}

// A smooth round bump (Gaussian, sigma s pixels) centred at (cx, cy) in pixel coordinates (pixel
// centres at integers, as OpenCV), on a constant background.
std::vector<std::uint8_t> blob(double cx, double cy, double s, int n = 256) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(n) * n);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const double d2 = (c - cx) * (c - cx) + (r - cy) * (r - cy);
            img[static_cast<std::size_t>(r) * n + c] = static_cast<std::uint8_t>(std::lround(40 + 200 * std::exp(-d2 / (2 * s * s))));
        }
    return img;
}

}  // namespace

TEST(Sift, BlankImageHasNoDescriptors) {
    EXPECT_EQ(sift_descriptors(std::vector<std::uint8_t>(256 * 256, 0), 256).rows(), 0);
    EXPECT_EQ(sift_descriptors(std::vector<std::uint8_t>(64 * 64, 200), 64).rows(), 0);
    EXPECT_THROW(sift_descriptors(std::vector<std::uint8_t>(10, 0), 256), InputError);
    EXPECT_THROW(sift_descriptors({}, 0), InputError);
}

TEST(Sift, EveryBackendFindsKeypointsDeterministically) {
    const auto bumpy = synthetic_depth(true);
    std::vector<float> depth(bumpy.size());
    for (size_t i = 0; i < bumpy.size(); ++i) depth[i] = bumpy[i] / 255.f;
    std::map<std::string, long> counts;
    for (const char* name : {"opencv", "opencv-half", "opencv-fast", "vlfeat"}) {
        SiftOptions o;
        o.backend = parse_sift_backend(name);
        EXPECT_EQ(sift_backend_name(o.backend), name);
        const SiftDescriptors d = depth_sift_descriptors(depth, 256, o);
        counts[name] = static_cast<long>(d.rows());
        EXPECT_GE(d.rows(), 5) << name;
        EXPECT_TRUE(d.allFinite()) << name;
        EXPECT_GE(d.minCoeff(), 0.f) << name;
        EXPECT_LE(d.maxCoeff(), 255.f) << name;
        // Descriptors of the scale OpenCV uses (norm about 512) for every backend.
        EXPECT_NEAR(d.row(0).norm(), 512.f, 100.f) << name;
        EXPECT_TRUE(d == depth_sift_descriptors(depth, 256, o)) << name;  // deterministic
        EXPECT_EQ(depth_sift_descriptors(std::vector<float>(256 * 256, 0.3f), 256, o).rows(), 0) << name;  // blank
        EXPECT_THROW(depth_sift_descriptors(depth, 255, o), InputError) << name;
    }
    std::printf("[sift] bumpy sphere keypoints: opencv %ld, opencv-half %ld, opencv-fast %ld, vlfeat %ld\n",
                counts["opencv"], counts["opencv-half"], counts["opencv-fast"], counts["vlfeat"]);
    // The 8-bit and the float input agree for OpenCV (the float depth is rounded to the same bytes).
    EXPECT_TRUE(depth_sift_descriptors(depth, 256, {}) == sift_descriptors(bumpy, 256));
    EXPECT_THROW(parse_sift_backend("surf"), InputError);
}

TEST(Sift, SyntheticDepthKeypointCounts) {
    const auto figure = synthetic_depth(false), bumpy = synthetic_depth(true);
    SiftOptions opencv;  // the counts of kDefaultContrastThreshold's table are OpenCV's
    opencv.backend = SiftBackend::OpenCV;
    const auto f = sift_descriptors(figure, 256, opencv), b = sift_descriptors(bumpy, 256, opencv);
    SiftOptions opencv_default = opencv;
    opencv_default.contrast_threshold = 0.04;
    const auto b04 = sift_descriptors(bumpy, 256, opencv_default);
    std::printf("[sift] keypoints (contrast threshold %.4g): stick figure %ld, bumpy sphere %ld; bumpy sphere at "
                "OpenCV's default 0.04: %ld\n",
                kDefaultContrastThreshold, static_cast<long>(f.rows()), static_cast<long>(b.rows()),
                static_cast<long>(b04.rows()));
    EXPECT_GE(f.rows(), 10);
    EXPECT_LE(f.rows(), 100);
    EXPECT_GE(b.rows(), 10);
    EXPECT_LE(b.rows(), 150);
    EXPECT_GT(b.rows(), b04.rows());  // the lowered threshold keeps the weak interior extrema
    EXPECT_TRUE(f.allFinite());
    EXPECT_GE(f.minCoeff(), 0.f);
    EXPECT_TRUE(f == sift_descriptors(figure, 256, opencv));  // deterministic
}

TEST(Sift, BackendNamesRoundTrip) {
    for (const char* name : {"opencv", "opencv-half", "opencv-fast", "opencv-octave0", "opencv-octave0-fine", "vlfeat"})
        EXPECT_EQ(sift_backend_name(parse_sift_backend(name)), name);
    try {
        parse_sift_backend("surf");
        ADD_FAILURE() << "unknown backend accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("opencv-fast"), std::string::npos) << e.what();  // names the choices
    }
}

// opencv-fast detects on the half view (as opencv-half) and describes on the full view: the same
// keypoints as opencv-half, every one at octave >= 0 of the view (no doubled image), while opencv's
// own detector also finds keypoints in its doubled octave -1; descriptors in OpenCV's format, one
// per keypoint, but not opencv-half's (they come from the full-resolution pyramid).
TEST(Sift, FastBackendDescribesHalfViewKeypointsAtTheViewResolution) {
    const auto bumpy = synthetic_depth(true);
    SiftOptions half, fast, full;
    half.backend = SiftBackend::OpenCVHalf;
    fast.backend = SiftBackend::OpenCVFast;
    full.backend = SiftBackend::OpenCV;
    const SiftFeatures h = sift_features(bumpy, 256, half), f = sift_features(bumpy, 256, fast),
                       o = sift_features(bumpy, 256, full);
    ASSERT_GE(f.keypoints.size(), 5u);
    ASSERT_EQ(f.keypoints.size(), h.keypoints.size());
    ASSERT_EQ(static_cast<size_t>(f.descriptors.rows()), f.keypoints.size());
    ASSERT_EQ(static_cast<size_t>(o.descriptors.rows()), o.keypoints.size());
    for (size_t i = 0; i < f.keypoints.size(); ++i) {
        const SiftKeypoint &a = f.keypoints[i], &b = h.keypoints[i];
        expect_same_keypoint(a, b);
        EXPECT_GE(a.octave, 0);
        EXPECT_GE(a.x, 0.f);
        EXPECT_LT(a.x, 256.f);
        EXPECT_GE(a.y, 0.f);
        EXPECT_LT(a.y, 256.f);
    }
    const long doubled = std::count_if(o.keypoints.begin(), o.keypoints.end(), [](const SiftKeypoint& k) { return k.octave < 0; });
    EXPECT_GT(doubled, 0);  // opencv's first octave is the doubled view
    expect_opencv_descriptor_format(f.descriptors);
    EXPECT_FALSE(f.descriptors == h.descriptors);
    // Close to opencv-half's all the same (same keypoint, same scale, nearly the same image).
    double mean_cos = 0;
    for (Eigen::Index r = 0; r < f.descriptors.rows(); ++r)
        mean_cos += f.descriptors.row(r).dot(h.descriptors.row(r)) / (f.descriptors.row(r).norm() * h.descriptors.row(r).norm());
    mean_cos /= double(f.descriptors.rows());
    std::printf("[sift] opencv-fast vs opencv-half: %zu keypoints, mean cosine of the descriptors %.3f; opencv %zu "
                "keypoints (%ld in the doubled octave)\n",
                f.keypoints.size(), mean_cos, o.keypoints.size(), doubled);
    EXPECT_GT(mean_cos, 0.8);
    const SiftFeatures again = sift_features(bumpy, 256, fast);
    EXPECT_TRUE(again.descriptors == f.descriptors);  // deterministic
}

// Keypoints are where the feature is in the view, as cv::SIFT::compute without doubling reads them
// (opencv-fast's descriptors are taken there): a round bump centred between pixels and one centred on
// a pixel are found at their centres by every OpenCV backend (a mapping off by half a pixel, or
// OpenCV's own 0.25-pixel offset of doubled images left in, fails).
TEST(Sift, KeypointsAreInTheViewsPixelCoordinates) {
    for (const auto& [cx, cy] : std::vector<std::pair<double, double>>{{100.5, 140.5}, {131.0, 90.0}}) {
        const auto img = blob(cx, cy, 6.0);
        for (const SiftBackend b : {SiftBackend::OpenCV, SiftBackend::OpenCVHalf, SiftBackend::OpenCVFast, SiftBackend::OpenCVOctave0}) {
            SiftOptions o;
            o.backend = b;
            const SiftFeatures f = sift_features(img, 256, o);
            double best = 1e9;
            for (const SiftKeypoint& k : f.keypoints) best = std::min(best, std::hypot(k.x - cx, k.y - cy));
            EXPECT_LT(best, 0.15) << sift_backend_name(b) << " at (" << cx << ", " << cy << ")";
        }
    }
}

// opencv-octave0 reproduces OpenCV's own keypoints at octaves >= 0 without OpenCV's doubled image:
// on the synthetic views, nearly every keypoint opencv reports at octave o >= 0 has an opencv-octave0
// keypoint within half a pixel of that octave (2^o / 2 view pixels), of the same size (10%) and
// orientation (5 degrees), with nearly opencv's descriptor (mean cosine > 0.98: our port of OpenCV's
// descriptor on the same grid); the counts per octave agree within 15%; nothing at octave -1;
// descriptors one per keypoint in OpenCV's format; deterministic.
TEST(Sift, Octave0BackendReproducesOpenCVsKeypointsFromOctaveZero) {
    SiftOptions full, oct0;
    full.backend = SiftBackend::OpenCV;
    oct0.backend = SiftBackend::OpenCVOctave0;
    std::map<int, long> reference, ours, matched;
    double cosine_sum = 0;
    for (const bool bumps : {true, false}) {
        const auto img = synthetic_depth(bumps);
        const SiftFeatures o = sift_features(img, 256, full), f = sift_features(img, 256, oct0);
        ASSERT_EQ(static_cast<size_t>(f.descriptors.rows()), f.keypoints.size());
        for (const SiftKeypoint& k : f.keypoints) {
            EXPECT_GE(k.octave, 0);
            ++ours[k.octave];
        }
        for (const SiftKeypoint& k : o.keypoints) {
            if (k.octave < 0) continue;
            ++reference[k.octave];
            const double tolerance = 0.5 * double(1 << k.octave);
            for (size_t j = 0; j < f.keypoints.size(); ++j) {
                const SiftKeypoint& q = f.keypoints[j];
                double angle = std::abs(q.angle - k.angle);
                angle = std::min(angle, 360 - angle);
                if (std::hypot(q.x - k.x, q.y - k.y) < tolerance && std::abs(std::log(q.size / k.size)) < 0.1 && angle < 5) {
                    ++matched[k.octave];
                    const auto a = o.descriptors.row(&k - o.keypoints.data()), b = f.descriptors.row(static_cast<Eigen::Index>(j));
                    cosine_sum += a.dot(b) / (a.norm() * b.norm());
                    break;
                }
            }
        }
        expect_opencv_descriptor_format(f.descriptors);
        const SiftFeatures again = sift_features(img, 256, oct0);
        EXPECT_TRUE(again.descriptors == f.descriptors);  // deterministic
    }
    long total = 0, total_matched = 0;
    for (const auto& [octave, n] : reference) {
        std::printf("[sift] octave %d: opencv %ld keypoints, opencv-octave0 %ld, opencv's matched %ld\n", octave, n, ours[octave],
                    matched[octave]);
        total += n;
        total_matched += matched[octave];
        if (n >= 10) {
            EXPECT_NEAR(double(ours[octave]), double(n), 0.15 * double(n)) << "octave " << octave;
        }
    }
    ASSERT_GE(reference[0], 10);  // the octave in question is populated
    EXPECT_GE(double(matched[0]), 0.9 * double(reference[0]));
    EXPECT_GE(double(total_matched), 0.9 * double(total));
    std::printf("[sift] mean cosine of matched descriptors %.4f\n", cosine_sum / double(total_matched));
    EXPECT_GT(cosine_sum / double(total_matched), 0.98);
}

// opencv-octave0-fine is opencv-octave0 plus keypoints of an extra, finer octave reported at octave
// -1: its keypoints at octaves >= 0 and their descriptors are opencv-octave0's, in the same order,
// after the octave -1 ones, which are smaller (finer scale) and inside the view; descriptors in
// OpenCV's format; deterministic.
TEST(Sift, Octave0FineBackendAddsAnOctaveMinusOne) {
    SiftOptions oct0, fine;
    oct0.backend = SiftBackend::OpenCVOctave0;
    fine.backend = SiftBackend::OpenCVOctave0Fine;
    EXPECT_EQ(SiftOptions{}.backend, SiftBackend::OpenCVOctave0Fine);  // the default extractor
    long extra_total = 0;
    for (const bool bumps : {true, false}) {
        const auto img = synthetic_depth(bumps);
        const SiftFeatures a = sift_features(img, 256, oct0), b = sift_features(img, 256, fine);
        ASSERT_EQ(static_cast<size_t>(b.descriptors.rows()), b.keypoints.size());
        size_t extra = 0;
        while (extra < b.keypoints.size() && b.keypoints[extra].octave == -1) ++extra;
        ASSERT_EQ(b.keypoints.size(), extra + a.keypoints.size()) << "bumps " << bumps;
        std::vector<float> fine_sizes, octave0_sizes;
        for (size_t i = 0; i < extra; ++i) {
            const SiftKeypoint& k = b.keypoints[i];
            EXPECT_GE(k.x, 0.f);
            EXPECT_LT(k.x, 256.f);
            EXPECT_GE(k.y, 0.f);
            EXPECT_LT(k.y, 256.f);
            fine_sizes.push_back(k.size);
        }
        for (size_t i = 0; i < a.keypoints.size(); ++i) {
            const SiftKeypoint &p = a.keypoints[i], &q = b.keypoints[extra + i];
            expect_same_keypoint(p, q);
            EXPECT_GE(q.octave, 0);
            if (q.octave == 0) octave0_sizes.push_back(q.size);
        }
        EXPECT_TRUE(b.descriptors.bottomRows(a.descriptors.rows()) == a.descriptors);
        if (!fine_sizes.empty() && !octave0_sizes.empty()) {
            std::sort(fine_sizes.begin(), fine_sizes.end());
            std::sort(octave0_sizes.begin(), octave0_sizes.end());
            EXPECT_LT(fine_sizes[fine_sizes.size() / 2], octave0_sizes[octave0_sizes.size() / 2]);
        }
        expect_opencv_descriptor_format(b.descriptors);
        EXPECT_TRUE(b.descriptors == sift_features(img, 256, fine).descriptors);  // deterministic
        std::printf("[sift] %s: opencv-octave0 %zu keypoints, opencv-octave0-fine %zu more at octave -1\n",
                    bumps ? "bumpy sphere" : "stick figure", a.keypoints.size(), extra);
        extra_total += static_cast<long>(extra);
    }
    EXPECT_GT(extra_total, 0);
}
