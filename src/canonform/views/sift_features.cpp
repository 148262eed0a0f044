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

const std::vector<std::string>& sift_backend_names() {
    static const std::vector<std::string> names = {"opencv", "opencv-half", "vlfeat", "opencv-fast"};
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
