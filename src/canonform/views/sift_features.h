// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: SIFT descriptors (difference-of-Gaussian keypoints) of one 8-bit depth view.
//
// Reference: D. G. Lowe, "Distinctive image features from scale-invariant keypoints", IJCV 60(2),
// 2004; Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape retrieval
// using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013 (Sec. 3.2);
// Pickup et al., Pattern Recognition 2015 (CM-BOF on canonical forms).
//
// Six extractors (SiftBackend; `--sift` in the tool and `retrieve`, a parameter of the view filter):
// - opencv: OpenCV's cv::SIFT on the 8-bit view, as described below. OpenCV doubles the image
//   before its first octave (first octave -1): a 512 x 512 pyramid for a 256 x 256 view, which is
//   most of its cost.
// - opencv-half: the same on the 8-bit view halved (area average), so that OpenCV's doubling puts
//   its first octave at the view's own resolution (VLFeat's first octave 0). About a quarter of
//   the pixels of `opencv` in the first octave; keypoints and descriptors both from the half view.
// - opencv-fast: opencv-half's keypoints (positions, scales, orientations) mapped to the full view,
//   and OpenCV's descriptors computed there (cv::SIFT::compute on provided keypoints: OpenCV 4.6
//   starts its pyramid at the smallest provided octave, here 0, so it does not double the view).
//   The descriptors see the view's full resolution, the detector costs what opencv-half's does
//   (measured: retrieval like opencv-half's, not opencv's - docs/sift.md).
//   Our departure from Lowe's single-pyramid pipeline: detection and description use two pyramids
//   (the half view's doubled image and the view itself) of the same scale.
// - opencv-octave0: opencv's own keypoints of octaves >= 0 without its doubled image. OpenCV 4.6's
//   detector (findScaleSpaceExtrema: 26-neighbour extrema of the DoG layers 1..3, integer
//   pre-threshold, adjustLocalExtrema's refinement with contrast and edge tests, orientation
//   histogram, keypoint packing) is re-implemented here on OpenCV's octave-0 grid: OpenCV's octave 0
//   is the nearest-neighbour half of its doubled image, i.e. the view resampled at i - 1/4 on both
//   axes (0.25 * I[i-1] + 0.75 * I[i]), blurred to sigma. That resampling, not the blur, is what a
//   plain first octave 0 on the view lacks (it finds a third of opencv's octave-0 keypoints).
//   Descriptors: OpenCV 4.6's calcSIFTDescriptor, ported, on the same pyramid (cv::SIFT::compute
//   would build a second pyramid, and takes 8-bit images only). Departure from opencv: no octave
//   -1 keypoints. Measured: 94% of opencv's octave-0 keypoints and all of octaves >= 1 found
//   (position within half a pixel of the octave, size 10%, angle 5 degrees), 7% more at octave 0,
//   descriptors of the matched keypoints opencv's (mean cosine 1.000) (docs/sift.md).
// - opencv-octave0-fine: opencv-octave0 plus an approximate octave -1: one more octave, on the view
//   itself (not resampled, not doubled), from sigma / 2 (the scale of OpenCV's doubled octave),
//   with 2 DoG layers, the same detector and descriptor; its keypoints are reported at octave -1.
//   Departure from opencv: OpenCV finds its octave -1 keypoints on the doubled view, which costs
//   four times the pixels; on the view itself 2 layers find about as many (3 layers find ten
//   times as many: the 8-bit steps). Measured: retrieval like opencv's, which opencv-octave0's
//   lacks (docs/sift.md).
// - vlfeat: VLFeat's vl_sift (Debian's libvlfeat-dev, 0.9.21) on the float depth image scaled to
//   [0, 255] (no 8-bit rounding) with VLFeat's defaults, as CM-BOF's public code calls it: first
//   octave 0, 3 levels per octave, peak threshold 0, edge threshold 10; one descriptor per
//   keypoint orientation (up to four), scaled as VLFeat's MATLAB wrapper does (512 times the unit
//   vector, saturated to 255), so the values have OpenCV's scale. VLFeat's bin order differs from
//   OpenCV's, so the descriptors of two backends must not share a codebook (the retrieval cache
//   keys include the backend).
// Keypoints per view, CPU seconds and retrieval measures of the three: docs/sift.md and docs/benchmarks.md.
//
// The opencv extractor is OpenCV's cv::SIFT (features2d, OpenCV >= 4.4). CM-BOF was published with
// VLFeat's SIFT at its defaults: peak threshold 0 and edge threshold 10. OpenCV's default
// contrastThreshold 0.04 rejects far more low-contrast extrema, which on smooth depth images leaves
// few keypoints. We therefore lower the contrast threshold (edge threshold 10 as in VLFeat).
//
// Measured keypoint counts and the chosen threshold (0.001): see kDefaultContrastThreshold below.
//
// Conventions: the image is row-major, size x size, one byte per pixel; 0 is the background (far).
// Descriptors are OpenCV's: 128 floats per keypoint, non-negative, L2 norm about 512 (OpenCV scales
// the unit-length, 0.2-clipped vector by 512 and saturates to [0, 255]).
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::views {

/// n x 128 SIFT descriptors, one per row (row-major so a row is one contiguous descriptor).
using SiftDescriptors = Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor>;

/// The default contrast threshold of SiftOptions, chosen so that keypoint counts on depth images
/// are comparable to VLFeat's defaults (peak threshold 0, edge threshold 10, first octave 0).
///
/// Measured (OpenCV 4.6 cv::SIFT vs. VLFeat 0.9.21 vl_sift_* at its defaults; keypoints counted with
/// one entry per orientation in both) on seven synthetic 256 x 256 8-bit depth images (orthographic
/// height fields, background 0, nearest point 255): sphere, torus, tilted box, two-sphere blob,
/// sphere with nine Gaussian bumps, capsule stick figure, rippled sphere:
///
///   extractor                       sphere torus box blob bumpy figure ripple | total
///   VLFeat (peak 0, edge 10)            4     4   26    8    40     29      7  |  118
///   OpenCV contrastThreshold 0.04       5    24    6   11     5     25      7  |   83
///   OpenCV contrastThreshold 0.01       5    24    6   11     9     25      7  |   87
///   OpenCV contrastThreshold 0.002      5    24    6   11     9     27      7  |   89
///   OpenCV contrastThreshold 0.001      5    24    6   17    19     28     12  |  111   <- default
///   OpenCV contrastThreshold 0.0005     5    24    6   19    53     28     15  |  150
///   OpenCV contrastThreshold 0          15    24    6   19    69     28     17  |  178
///
/// Silhouette extrema are strong (DoG of tens of gray levels) and survive any threshold; the gain
/// comes from weak interior extrema (surface detail: DoG below one gray level), which OpenCV's
/// default 0.04 (a DoG of about 3.4 gray levels with 3 layers) discards and VLFeat's peak
/// threshold 0 keeps. 0.001 gives the closest total; 0 also keeps quantisation artefacts on
/// smooth regions (the 10 extra zero-response keypoints on the plain sphere). Per-image counts
/// still differ (OpenCV doubles the image before the first octave, VLFeat does not; the box's
/// corners give VLFeat many more keypoints), so counts are comparable, not equal.
inline constexpr double kDefaultContrastThreshold = 0.001;

/// The SIFT implementation (see above).
enum class SiftBackend { OpenCV, OpenCVHalf, VLFeat, OpenCVFast, OpenCVOctave0, OpenCVOctave0Fine };

/// Every backend's name, in SiftBackend's order (which is also the order of the view filter's
/// `sift` enum): "opencv", "opencv-half", "vlfeat", "opencv-fast", "opencv-octave0",
/// "opencv-octave0-fine".
const std::vector<std::string>& sift_backend_names();
/// A name of sift_backend_names() (InputError naming the choices otherwise), and back.
SiftBackend parse_sift_backend(const std::string& name);
std::string sift_backend_name(SiftBackend backend);

/// One keypoint at the feature's position in the view's pixel coordinates (pixel centres at
/// integers). OpenCV reports positions 0.25 pixel off when it doubles the image (see
/// sift_features.cpp); that is corrected here (opencv-octave0's carry the same offset from its
/// resampled grid, corrected too), and opencv-half's and opencv-fast's keypoints are mapped from the
/// half view.
struct SiftKeypoint {
    float x = 0, y = 0;  ///< position (column, row)
    float size = 0;      ///< OpenCV's KeyPoint::size (diameter) for the OpenCV backends; VLFeat's sigma for vlfeat
    float angle = 0;     ///< orientation in degrees (OpenCV's convention for the OpenCV backends)
    int octave = 0;      ///< pyramid octave relative to the view (-1: opencv's doubled image, opencv-octave0-fine's
                         ///< extra octave; >= 0 for the others)
};

/// Keypoints and their descriptors (row i describes keypoints[i]).
struct SiftFeatures {
    std::vector<SiftKeypoint> keypoints;
    SiftDescriptors descriptors = SiftDescriptors(0, 128);
};

/// Options of sift_descriptors(); the names follow cv::SIFT::create. The thresholds apply to the
/// OpenCV backends; vlfeat uses VLFeat's defaults (peak 0, edge 10, first octave 0).
struct SiftOptions {
    SiftBackend backend = SiftBackend::OpenCVOctave0Fine;  ///< the extractor (default since issue 13: docs/sift.md)
    double contrast_threshold = kDefaultContrastThreshold;  ///< OpenCV contrastThreshold (>= 0)
    double edge_threshold = 10;   ///< principal-curvature ratio limit (VLFeat and OpenCV default 10)
    int max_features = 0;         ///< keep the strongest n keypoints; 0 = all
    double sigma = 1.6;           ///< Gaussian sigma of the first octave's base image
    int octave_layers = 3;        ///< DoG layers per octave
};

/// SIFT descriptors of the keypoints of one size x size 8-bit image (row-major, gray.size() ==
/// size * size). Returns n x 128 rows, in OpenCV's keypoint order (deterministic for a given
/// image). A blank (constant) image gives 0 rows. Throws InputError if size <= 0, the buffer size
/// does not match, or an option is out of range (negative threshold, octave_layers < 1, sigma <= 0,
/// max_features < 0).
SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size,
                                 const SiftOptions& options = {});

/// The same with the keypoints (sift_descriptors() is sift_features().descriptors).
SiftFeatures sift_features(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options = {});

/// The same for a depth image in [0, 1] (row-major, size x size): the OpenCV backends see it as
/// 8 bits (round(255 * depth)), vlfeat as floats 255 * depth. Same errors.
SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size, const SiftOptions& options = {});
SiftFeatures depth_sift_features(const std::vector<float>& depth, int size, const SiftOptions& options = {});

}  // namespace canonform::views
