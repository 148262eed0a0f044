// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of opencv_sift.h: OpenCV's SIFT through its public API as the `opencv` extractor, and
// OpenCV's descriptors of given keypoints.
#include "canonform/views/opencv_sift.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace canonform;
using namespace canonform::views;

namespace {

constexpr int kN = 256;

// A sphere with nine Gaussian bumps (bumps = true) or a capsule stick figure, as an image with
// values in [0, 1] (background 0) rounded to 8 bits as OpenCV sees it.
std::vector<float> synthetic_depth(bool bumps) {
    std::vector<float> img(static_cast<size_t>(kN) * kN, 0.f);
    for (int r = 0; r < kN; ++r)
        for (int c = 0; c < kN; ++c) {
            const double x = (c + 0.5) / kN * 2 - 1, y = (r + 0.5) / kN * 2 - 1;
            const double z = test::synthetic_scene_height(bumps, x, y);
            if (z > -1.5)
                img[static_cast<size_t>(r) * kN + c] =
                    static_cast<float>(std::round(std::clamp(1.0 + 254.0 * (z + 1) / 2, 1.0, 255.0)) / 255);
        }
    return img;
}

}  // namespace

TEST(OpenCVSift, RegisteredAsTheOpencvBackend) {
    register_opencv_sift();
    EXPECT_TRUE(sift_backend_available(SiftBackend::OpenCV));
    SiftOptions o;
    o.backend = SiftBackend::OpenCV;
    const auto img = synthetic_depth(true);
    const SiftFeatures a = sift_features(img, kN, o), b = opencv_sift_features(img, kN, o);
    ASSERT_GE(a.keypoints.size(), 10u);
    EXPECT_TRUE(a.descriptors == b.descriptors);
    EXPECT_TRUE(a.descriptors == sift_features(img, kN, o).descriptors);  // deterministic
    long doubled = 0;
    for (const SiftKeypoint& k : a.keypoints) doubled += k.octave < 0;
    EXPECT_GT(doubled, 0);  // OpenCV's first octave is the doubled view
    for (Eigen::Index r = 0; r < a.descriptors.rows(); ++r) {
        EXPECT_NEAR(a.descriptors.row(r).norm(), 512.f, 100.f);
        EXPECT_EQ(a.descriptors.row(r), a.descriptors.row(r).array().round().matrix());
    }
}

// The counts behind kDefaultContrastThreshold: OpenCV's default 0.04 drops the weak interior extrema
// that 0.001 keeps.
TEST(OpenCVSift, LowerContrastThresholdKeepsWeakInteriorExtrema) {
    const auto figure = synthetic_depth(false), bumpy = synthetic_depth(true);
    SiftOptions o;
    const auto f = opencv_sift_features(figure, kN, o), b = opencv_sift_features(bumpy, kN, o);
    SiftOptions opencv_default = o;
    opencv_default.contrast_threshold = 0.04;
    const auto b04 = opencv_sift_features(bumpy, kN, opencv_default);
    std::printf(
        "[opencv] keypoints (contrast threshold %.4g): stick figure %zu, bumpy sphere %zu; bumpy sphere at "
        "OpenCV's default 0.04: %zu\n",
        kDefaultContrastThreshold, f.keypoints.size(), b.keypoints.size(), b04.keypoints.size());
    EXPECT_GE(f.keypoints.size(), 10u);
    EXPECT_LE(f.keypoints.size(), 100u);
    EXPECT_GE(b.keypoints.size(), 10u);
    EXPECT_LE(b.keypoints.size(), 150u);
    EXPECT_GT(b.keypoints.size(), b04.keypoints.size());
}

// Positions in the view's pixel coordinates: a round bump centred between pixels and one centred
// on a pixel are found at their centres (OpenCV's 0.25-pixel offset of doubled images moved back).
TEST(OpenCVSift, KeypointsAreInTheViewsPixelCoordinates) {
    for (const auto& [cx, cy] : std::vector<std::pair<double, double>>{{100.5, 140.5}, {131.0, 90.0}}) {
        std::vector<float> img(static_cast<size_t>(kN) * kN);
        for (int r = 0; r < kN; ++r)
            for (int c = 0; c < kN; ++c) {
                const double d2 = (c - cx) * (c - cx) + (r - cy) * (r - cy);
                img[static_cast<size_t>(r) * kN + c] =
                    static_cast<float>(std::lround(40 + 200 * std::exp(-d2 / 72.0)) / 255.0);
            }
        const SiftFeatures f = opencv_sift_features(img, kN);
        double best = 1e9;
        for (const SiftKeypoint& k : f.keypoints) best = std::min(best, std::hypot(k.x - cx, k.y - cy));
        EXPECT_LT(best, 0.15) << "at (" << cx << ", " << cy << ")";
    }
}

// opencv_descriptors_at() hands keypoints to OpenCV as OpenCV's own detector reports them: given
// OpenCV's keypoints back (with their octaves, so the doubled image too), OpenCV's compute()
// reproduces the descriptors of its detectAndCompute().
TEST(OpenCVSift, DescriptorsAtOpenCVsOwnKeypointsAreItsOwnDescriptors) {
    for (const bool bumps : {true, false}) {
        const auto img = synthetic_depth(bumps);
        const SiftFeatures f = opencv_sift_features(img, kN);
        ASSERT_GE(f.keypoints.size(), 10u);
        const SiftDescriptors d = opencv_descriptors_at(img, kN, f.keypoints);
        ASSERT_EQ(d.rows(), f.descriptors.rows());
        double worst = 1;
        for (Eigen::Index r = 0; r < d.rows(); ++r)
            worst = std::min(worst, double(d.row(r).dot(f.descriptors.row(r)) /
                                           (d.row(r).norm() * f.descriptors.row(r).norm())));
        std::printf("[opencv] %s: compute() on detectAndCompute()'s %zu keypoints: lowest cosine %.4f\n",
                    bumps ? "bumpy sphere" : "stick figure", f.keypoints.size(), worst);
        EXPECT_GT(worst, 0.99);
    }
}
