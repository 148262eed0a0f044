// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/opencv_sift.h"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <algorithm>
#include <cmath>

namespace canonform::views {
namespace {

// OpenCV's doubled first octave puts reported positions 0.25 pixel right of and below the feature.
constexpr float kDoubledOffset = 0.25f;

int keypoint_octave(const cv::KeyPoint& k) {
    return static_cast<std::int8_t>(k.octave & 255);
}

cv::Mat as_bytes(const std::vector<float>& image, int size) {
    cv::Mat m(size, size, CV_8UC1);
    for (int r = 0; r < size; ++r)
        for (int c = 0; c < size; ++c) {
            const double v =
                image[static_cast<size_t>(r) * static_cast<size_t>(size) + static_cast<size_t>(c)];
            m.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(std::round(255.0 * std::clamp(v, 0.0, 1.0)));
        }
    return m;
}

cv::Ptr<cv::SIFT> make_sift(const SiftOptions& o) {
    return cv::SIFT::create(o.max_features, o.octave_layers, o.contrast_threshold, o.edge_threshold, o.sigma);
}

SiftDescriptors to_eigen(const cv::Mat& d, size_t rows) {
    if (d.empty() && rows == 0) return SiftDescriptors(0, 128);
    if (d.cols != 128 || d.type() != CV_32F || d.rows != static_cast<int>(rows))
        throw NumericalError("SIFT: OpenCV returned descriptors of an unexpected shape or type.");
    SiftDescriptors out(d.rows, 128);
    for (int r = 0; r < d.rows; ++r) {
        const float* src = d.ptr<float>(r);
        for (int c = 0; c < 128; ++c) out(r, c) = src[c];
    }
    return out;
}

}  // namespace

void register_opencv_sift() {
    register_sift_extractor(SiftBackend::OpenCV, &opencv_sift_features);
}

SiftFeatures opencv_sift_features(const std::vector<float>& image, int size, const SiftOptions& options) {
    const cv::Mat bytes = as_bytes(image, size);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    make_sift(options)->detectAndCompute(bytes, cv::noArray(), keypoints, descriptors);
    SiftFeatures out;
    out.descriptors = to_eigen(descriptors, keypoints.size());
    for (const cv::KeyPoint& k : keypoints)
        out.keypoints.push_back({k.pt.x - kDoubledOffset, k.pt.y - kDoubledOffset, k.size, k.angle,
                                 keypoint_octave(k), k.response});
    return out;
}

SiftDescriptors opencv_descriptors_at(const std::vector<float>& image, int size,
                                      const std::vector<SiftKeypoint>& keypoints,
                                      const SiftOptions& options) {
    if (keypoints.empty()) return SiftDescriptors(0, 128);
    bool doubled = false;
    for (const SiftKeypoint& k : keypoints) doubled = doubled || k.octave < 0;
    const float offset = doubled ? kDoubledOffset : 0.f;
    std::vector<cv::KeyPoint> cv_keys;
    for (const SiftKeypoint& k : keypoints) {
        // sigma in the keypoint's octave, and the layer sigma0 2^(layer / s) nearest it.
        const double sigma = 0.5 * k.size / std::ldexp(1.0, k.octave);
        const int layer = std::clamp(
            static_cast<int>(std::lround(options.octave_layers * std::log2(sigma / options.sigma))), 0,
            options.octave_layers + 2);
        cv::KeyPoint c(k.x + offset, k.y + offset, k.size, k.angle, k.response);
        c.octave = (k.octave & 255) | (layer << 8);
        cv_keys.push_back(c);
    }
    const size_t n = cv_keys.size();
    cv::Mat descriptors;
    make_sift(options)->compute(as_bytes(image, size), cv_keys, descriptors);
    if (cv_keys.size() != n) throw NumericalError("SIFT: OpenCV dropped keypoints in compute().");
    return to_eigen(descriptors, n);
}

}  // namespace canonform::views
