#include "canonform/views/sift_features.h"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <cmath>
#include <string>

namespace canonform::views {

SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    if (size <= 0) throw InputError("SIFT: the image size must be positive (got " + std::to_string(size) + ").");
    const size_t expected = static_cast<size_t>(size) * static_cast<size_t>(size);
    if (gray.size() != expected)
        throw InputError("SIFT: the image buffer has " + std::to_string(gray.size()) + " bytes, expected " +
                         std::to_string(expected) + " for a " + std::to_string(size) + " x " +
                         std::to_string(size) + " image.");
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
    if (constant) return SiftDescriptors(0, 128);

    const cv::Mat image(size, size, CV_8UC1, const_cast<std::uint8_t*>(gray.data()));
    cv::Ptr<cv::SIFT> sift = cv::SIFT::create(options.max_features, options.octave_layers,
                                              options.contrast_threshold, options.edge_threshold, options.sigma);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    sift->detectAndCompute(image, cv::noArray(), keypoints, descriptors);
    if (descriptors.empty()) return SiftDescriptors(0, 128);
    if (descriptors.cols != 128 || descriptors.type() != CV_32F)
        throw NumericalError("SIFT: OpenCV returned descriptors of an unexpected shape or type.");
    SiftDescriptors out(descriptors.rows, 128);
    for (int r = 0; r < descriptors.rows; ++r) {
        const float* src = descriptors.ptr<float>(r);
        for (int c = 0; c < 128; ++c) out(r, c) = src[c];
    }
    return out;
}

}  // namespace canonform::views
