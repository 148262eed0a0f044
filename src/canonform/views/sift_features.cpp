// SPDX-License-Identifier: GPL-3.0-or-later
// The SIFT entry points of sift_features.h: the backend registry, the checks of the input, and the
// dispatch to the extractor (the canonform extractor: sift_pyramid.h, sift_extractor.h).
#include "canonform/views/sift_features.h"

#include "canonform/views/sift_extractor.h"
#include "canonform/views/sift_simd.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

namespace canonform::views {

// The backend registry.

const std::vector<std::string>& sift_backend_names() {
    static const std::vector<std::string> names = {"canonform", "opencv"};
    return names;
}

const std::vector<std::string>& builtin_sift_backend_names() {
    static const std::vector<std::string> names = {"canonform"};
    return names;
}

SiftBackend parse_sift_backend(const std::string& name) {
    const auto& names = sift_backend_names();
    std::string choices;
    for (size_t k = 0; k < names.size(); ++k) {
        if (names[k] == name) return static_cast<SiftBackend>(k);
        choices += (k ? ", " : "") + names[k];
    }
    for (const char* removed :
         {"opencv-half", "opencv-fast", "opencv-octave0", "opencv-octave0-fine", "vlfeat"})
        if (name == removed)
            throw InputError("SIFT: the backend '" + name +
                             "' was removed (issue 23: its code was not written in this project, " +
                             "or it was measured no better than the others); 'canonform' replaces it (" +
                             choices + ").");
    throw InputError("SIFT: unknown backend '" + name + "' (" + choices + ").");
}

std::string sift_backend_name(SiftBackend backend) {
    return sift_backend_names().at(static_cast<size_t>(backend));
}

namespace {

std::array<std::atomic<SiftExtractor>, 2> g_extractors{};

}  // namespace

void register_sift_extractor(SiftBackend backend, SiftExtractor extractor) {
    g_extractors.at(static_cast<size_t>(backend)).store(extractor);
}

bool sift_backend_available(SiftBackend backend) {
    return backend == SiftBackend::Canonform ||
           g_extractors.at(static_cast<size_t>(backend)).load() != nullptr;
}

namespace {

using namespace sift;

// One pass over an image: whether every value is finite, whether all are equal, and the box of the
// non-zero pixels.
struct ImageScan {
    bool finite = true, constant = true;
    Rect box;
};

ImageScan scan_image(const float* v, int size) {
    ImageScan r;
    r.box = {size, size, 0, 0};
    const v4f zero = splat4(0.f), first = splat4(v[0]);
    v4f nan_check = zero;  // v - v is 0 for finite v, NaN otherwise
    unsigned differs = 0;
    for (int y = 0; y < size; ++y) {
        const float* row = v + static_cast<size_t>(y) * static_cast<size_t>(size);
        int lo = -1, hi = -1, x = 0;
        for (; x + 4 <= size; x += 4) {
            const v4f q = load4(row + x);
            nan_check += q - q;
            differs |= mask4(q != first);
            const unsigned m = mask4(q != zero);
            if (m) {
                if (lo < 0) lo = x + __builtin_ctz(m);
                hi = x + 31 - __builtin_clz(m);
            }
        }
        for (; x < size; ++x) {
            r.finite = r.finite && std::isfinite(row[x]);
            differs |= row[x] != v[0] ? 1u : 0u;
            if (row[x] != 0.f) {
                if (lo < 0) lo = x;
                hi = x;
            }
        }
        if (lo < 0) continue;
        r.box = {std::min(r.box.x0, lo), std::min(r.box.y0, y), std::max(r.box.x1, hi + 1),
                 std::max(r.box.y1, y + 1)};
    }
    r.finite = r.finite && mask4(nan_check == zero) == 15u;
    r.constant = differs == 0;
    return r;
}

// The 8-bit view of depth_sift_features: image[i] = round(255 clamp(depth[i], 0, 1)) / 255 as the
// truncation of x + 0.5 (exact, see there), NaN for NaN. Four lanes at a time (sift_simd.h: one
// AVX2 instruction in the AVX2 clone, two SSE2 ones elsewhere), each doing the scalar tail's
// operations in its order: float to double (exact), std::clamp's choices, * 255, + 0.5, truncation to
// int, to float, / 255.
typedef double v4d __attribute__((vector_size(32)));
CANONFORM_CLONES void to_gray_levels(const float* depth, float* image, size_t n) {
    const v4d zero = {0.0, 0.0, 0.0, 0.0}, one = {1.0, 1.0, 1.0, 1.0};
    const v4d k255 = {255.0, 255.0, 255.0, 255.0}, half = {0.5, 0.5, 0.5, 0.5};
    const v4f nan = splat4(std::numeric_limits<float>::quiet_NaN());
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const v4f f = load4(depth + i);
        if (!mask4(f != splat4(0.f))) {  // background (0 or -0, which the lines below also make +0)
            store4(image + i, splat4(0.f));
            continue;
        }
        const v4i ok = f == f;  // not NaN
        const v4d v = __builtin_convertvector(select4(ok, f, splat4(0.f)), v4d);
        const v4d x = k255 * (v < zero ? zero : (one < v ? one : v));
        const v4f g = __builtin_convertvector(__builtin_convertvector(x + half, v4i), v4f) / splat4(255.f);
        store4(image + i, select4(ok, g, nan));
    }
    for (; i < n; ++i) {
        const double x = 255.0 * std::clamp(static_cast<double>(depth[i]), 0.0, 1.0);
        image[i] = x == x ? static_cast<float>(static_cast<int>(x + 0.5)) / 255.f
                          : std::numeric_limits<float>::quiet_NaN();
    }
}

void check_size(size_t have, int size, const char* unit) {
    if (size <= 0)
        throw InputError("SIFT: the image size must be positive (got " + std::to_string(size) + ").");
    const size_t expected = static_cast<size_t>(size) * static_cast<size_t>(size);
    if (have != expected)
        throw InputError("SIFT: the image buffer has " + std::to_string(have) + " " + unit + ", expected " +
                         std::to_string(expected) + " for a " + std::to_string(size) + " x " +
                         std::to_string(size) + " image.");
}

void check_options(const SiftOptions& o) {
    if (!(o.contrast_threshold >= 0) || !std::isfinite(o.contrast_threshold))
        throw InputError("SIFT: contrast_threshold must be a finite value >= 0.");
    if (!(o.edge_threshold > 0) || !std::isfinite(o.edge_threshold))
        throw InputError("SIFT: edge_threshold must be a finite value > 0.");
    if (!(o.sigma > 0) || !std::isfinite(o.sigma)) throw InputError("SIFT: sigma must be > 0.");
    if (o.octave_layers < 1 || o.octave_layers > 16)
        throw InputError("SIFT: octave_layers must be in 1..16.");
    if (o.max_features < 0) throw InputError("SIFT: max_features must be >= 0 (0 = all).");
    if (!(o.input_blur >= 0) || !(o.input_blur < 0.5 * o.sigma))
        throw InputError("SIFT: input_blur must be >= 0 and below sigma / 2.");
    if (!sift_backend_available(o.backend)) {
        std::string have;
        for (const auto& n : sift_backend_names())
            if (sift_backend_available(parse_sift_backend(n))) have += (have.empty() ? "" : ", ") + n;
        throw InputError(
            "SIFT: the backend '" + sift_backend_name(o.backend) + "' is not part of this program (" + have +
            " are; opencv needs OpenCV: it is in the canonform tool and the Python package built "
            "from source, not in the plugins or the portable wheel).");
    }
}

}  // namespace

SiftFeatures sift_features(const std::vector<float>& image, int size, const SiftOptions& options) {
    check_size(image.size(), size, "values");
    check_options(options);
    const ImageScan scan = scan_image(image.data(), size);
    if (!scan.finite) throw InputError("SIFT: the image has a non-finite value.");
    if (scan.constant) return {};
    if (options.backend != SiftBackend::Canonform)
        return g_extractors.at(static_cast<size_t>(options.backend)).load()(image, size, options);
    return sift::Extractor(image.data(), size, scan.box, options).run();
}

SiftDescriptors sift_descriptors(const std::vector<float>& image, int size, const SiftOptions& options) {
    return sift_features(image, size, options).descriptors;
}

SiftFeatures sift_features(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options) {
    check_size(gray.size(), size, "bytes");
    std::vector<float> image(gray.size());
    for (size_t i = 0; i < gray.size(); ++i) image[i] = static_cast<float>(gray[i]) / 255.f;
    return sift_features(image, size, options);
}

SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size,
                                 const SiftOptions& options) {
    return sift_features(gray, size, options).descriptors;
}

SiftFeatures depth_sift_features(const std::vector<float>& depth, int size, const SiftOptions& options) {
    check_size(depth.size(), size, "values");
    return depth_sift_features(depth.data(), size, options);
}

SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size,
                                       const SiftOptions& options) {
    return depth_sift_features(depth, size, options).descriptors;
}

SiftFeatures depth_sift_features(const float* depth, int size, const SiftOptions& options) {
    check_size(static_cast<size_t>(std::max(size, 0)) * static_cast<size_t>(std::max(size, 0)), size,
               "values");
    // The 8-bit view, round(255 depth) / 255, for both extractors (step 1), into a buffer kept per
    // thread. round(x) for x = 255 clamp(depth) in [0, 255] is the truncation of x + 0.5: x, 255
    // times a float, has at most 32 significant bits, so x + 0.5 is exact unless x < 2^-14, where
    // both are 0 (checked for every float in [0, 1]). A NaN stays NaN (sift_features refuses it).
    const size_t n = static_cast<size_t>(size) * static_cast<size_t>(size);
    thread_local std::vector<float> image;
    image.resize(n);
    to_gray_levels(depth, image.data(), n);
    return sift_features(image, size, options);
}

SiftDescriptors depth_sift_descriptors(const float* depth, int size, const SiftOptions& options) {
    return depth_sift_features(depth, size, options).descriptors;
}

}  // namespace canonform::views
