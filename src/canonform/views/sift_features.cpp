#include "canonform/views/sift_features.h"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <vl/sift.h>
}

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace canonform::views {

SiftBackend parse_sift_backend(const std::string& name) {
    if (name == "opencv") return SiftBackend::OpenCV;
    if (name == "opencv-half") return SiftBackend::OpenCVHalf;
    if (name == "vlfeat") return SiftBackend::VLFeat;
    throw InputError("SIFT: unknown backend '" + name + "' (opencv, opencv-half or vlfeat).");
}

std::string sift_backend_name(SiftBackend backend) {
    switch (backend) {
        case SiftBackend::OpenCV: return "opencv";
        case SiftBackend::OpenCVHalf: return "opencv-half";
        case SiftBackend::VLFeat: return "vlfeat";
    }
    return "opencv";
}

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
SiftDescriptors vlfeat_sift(const std::vector<float>& image, int size) {
    std::unique_ptr<VlSiftFilt, void (*)(VlSiftFilt*)> f(vl_sift_new(size, size, -1, 3, 0), vl_sift_delete);
    if (!f) throw NumericalError("SIFT: VLFeat could not allocate its filter.");
    vl_sift_set_peak_thresh(f.get(), 0.0);
    vl_sift_set_edge_thresh(f.get(), 10.0);
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
            }
        }
        err = vl_sift_process_next_octave(f.get());
    }
    SiftDescriptors out(static_cast<Eigen::Index>(rows.size() / 128), 128);
    std::copy(rows.begin(), rows.end(), out.data());
    return out;
}

}  // namespace

SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size, const SiftOptions& options) {
    check_size(depth.size(), size, "values");
    if (options.backend != SiftBackend::VLFeat) {
        std::vector<std::uint8_t> g(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            g[i] = static_cast<std::uint8_t>(std::round(255.0 * std::clamp(static_cast<double>(depth[i]), 0.0, 1.0)));
        return sift_descriptors(g, size, options);
    }
    bool constant = true;
    for (size_t k = 1; k < depth.size() && constant; ++k) constant = depth[k] == depth[0];
    if (constant) return SiftDescriptors(0, 128);
    std::vector<float> image(depth.size());
    for (size_t i = 0; i < depth.size(); ++i) image[i] = 255.f * std::clamp(depth[i], 0.f, 1.f);
    return vlfeat_sift(image, size);
}

SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
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
    if (constant) return SiftDescriptors(0, 128);

    if (options.backend == SiftBackend::VLFeat) {
        std::vector<float> image(gray.begin(), gray.end());
        return vlfeat_sift(image, size);
    }
    cv::Mat image(size, size, CV_8UC1, const_cast<std::uint8_t*>(gray.data()));
    if (options.backend == SiftBackend::OpenCVHalf) {
        cv::Mat half;
        cv::resize(image, half, cv::Size(std::max(1, size / 2), std::max(1, size / 2)), 0, 0, cv::INTER_AREA);
        image = half;
    }
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
