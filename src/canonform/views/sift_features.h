// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: SIFT keypoints and descriptors of one depth view - the project's own implementation of
// Lowe's method, and the choice of extractor.
//
// Reference: D. G. Lowe, "Distinctive image features from scale-invariant keypoints", IJCV 60(2),
// 91-110, 2004 (below "Lowe", with its section and equation numbers); Z. Lian, A. Godil, X. Sun,
// J. Xiao, "CM-BOF: visual similarity-based 3D shape retrieval using Clock Matching and
// Bag-of-Features", Machine Vision and Applications 24, 2013 (Sec. 3.2: SIFT on each depth view);
// Pickup et al., Pattern Recognition 2015 (CM-BOF on canonical forms).
//
// This comment describes the algorithm; docs/sift.md says how to choose and use an extractor and
// gives the tests' and benchmarks' figures; docs/records/sift-extractor.md has the measurements
// behind the departures below.
//
// Extractors (SiftBackend; `--sift` of the tool's view commands and `retrieve`, the view filter's
// `sift` parameter):
// - canonform (default): the implementation below, written for this project from Lowe's paper.
//   It needs no other library.
// - opencv: OpenCV's cv::SIFT through its public API (opencv_sift.h). It lives in a library of its
//   own that the canonform tool links and registers; the view filter does not carry it.
// Descriptors of two extractors differ, so they never share a codebook (retrieval cache keys
// include the extractor).
//
// The canonform extractor, step by step (image values in [0, 1]; a depth view is taken as 8 bits,
// round(255 depth) / 255, as OpenCV takes it - measured: docs/records/sift-extractor.md).
// 1. Scale space (Lowe Sec. 3, eq. 1). L(x, y, sigma) = G(sigma) * I; D = L(k sigma) - L(sigma),
//    k = 2^(1/s), s = octave_layers (3, Lowe Sec. 3.2), sigma_0 = sigma (1.6, Lowe Sec. 3.3).
//    An octave holds s + 3 Gaussian images sigma_0 k^j (j = 0..s+2) and s + 2 DoG images; each
//    Gaussian image is the previous one blurred by sqrt(sigma_j^2 - sigma_(j-1)^2) (the incremental
//    blur of Lowe Sec. 3), and the next octave starts from image j = s (2 sigma_0) taking every
//    second pixel of every second row (Lowe Sec. 3). The view is taken to have blur input_blur =
//    0.5 (Lowe Sec. 3.3), so the first image is blurred by sqrt(sigma_0^2 - 0.5^2).
//    Octave 0 lies where Lowe's would: Lowe first doubles the image by linear interpolation (Sec.
//    3.3) and his octave 0 takes every second pixel of the doubled image's pyramid. With pixel
//    centres at half pixels, doubled pixel 2i is the view at i - 1/4, that is 0.75 v[i] + 0.25
//    v[i - 1] along each axis: that resampled view, blurred to sigma_0, is our octave 0, and its
//    keypoints are moved back by the quarter pixel. We do not compute the doubled image's own
//    octave (-1; four times the pixels). Instead, with fine_octave (default), an approximate octave
//    -1 on the view itself: one octave from sigma_0 / 2 with 2 DoG layers (k = 2^(1/2)), searched
//    in DoG images 1 and 2 (scales 1.13 and 1.6 pixels), keypoints reported at octave -1. (With 3
//    layers, or on the doubled grid, it finds the silhouette's pixel staircase: hundreds of
//    keypoints per view.) These choices are measured (docs/records/sift-extractor.md): octave 0
//    on the view's own grid lost first tier on the procedural collection, and the octave -1 gains
//    it.
//    Outside the view the image is 0 (background, which is also the view's own background). The
//    blur is a separable Gaussian truncated at 3 sigma and normalised to sum 1, its taps computed in
//    double by our own exp (numerics/portable_math.h) and rounded to float. (Departure: 4 sigma
//    before, as common; the shorter taps cost less, and retrieval held on every collection at hand
//    by the paired check of bench/run_quality_rule.sh: docs/benchmarks.md.) Each image is computed
//    only over its support - the bounding box of the view's non-zero pixels grown by 3 sigma_j -
//    outside which it is taken as 0: a view costs in proportion to the object's size, not the image's.
//    Octaves: while the octave's view is at least 8 pixels wide (6 for a 256 view).
// 2. Extrema (Lowe Sec. 3.1): a sample of DoG images j = 1..s larger than all 26 neighbours or
//    smaller than all of them, with |D| >= 0.5 t (a pre-test of ours: t is the contrast threshold
//    below). Searched where the three DoG images involved are computed (their supports'
//    intersection, less one pixel).
// 3. Sub-pixel refinement (Lowe Sec. 4, eqs. 2-3): the 3 x 3 system of D's Hessian and gradient
//    (central differences in x, y and scale) gives the offset x^; when a coordinate of x^ exceeds
//    0.5 the sample moves to the neighbour in that direction and the fit is repeated - at most 5
//    fits (a cap of ours), else the extremum is dropped, as is one whose Hessian is singular. A
//    move back to the previous sample (the extremum lies between the two) ends the fit when every
//    coordinate is within 0.6 (ours; such extrema were dropped otherwise, e.g. a blob centred
//    between two samples).
//    Contrast test (Lowe Sec. 4): |D(x^)| = |D + 0.5 dD/dx . x^| >= t, with
//    t = contrast_threshold / s: Lowe's threshold (0.03 on [0, 1]) in the convention of OpenCV's
//    public contrastThreshold parameter, which is divided by the layers per octave (the OpenCV
//    documentation of SIFT::create), so one option means the same for both extractors. Our default
//    0.001 (t = 0.00033, a twelfth of a gray level) keeps the weak interior extrema of depth
//    views: kDefaultContrastThreshold. The same t for the approximate octave -1.
//    Edge test (Lowe Sec. 4.1, eq. 4): the 2 x 2 spatial Hessian H at the sample must have
//    Det(H) > 0 and Tr(H)^2 / Det(H) < (r + 1)^2 / r, r = edge_threshold (10, Lowe).
//    Scale of a keypoint: sigma = sigma_0 k^(j + x^_scale) in octave pixels (the DoG image's
//    lower scale, Lowe's labelling of eq. 1), times 2^octave in view pixels.
// 4. Orientation (Lowe Sec. 5): in the Gaussian image j of the keypoint's DoG image (the closest
//    in scale, since |x^_scale| <= 0.5), gradients by central differences, m = sqrt(dx^2 + dy^2),
//    theta = atan2(dy, dx) (y = row, downwards: theta grows clockwise on screen, OpenCV's
//    documented KeyPoint::angle convention). A 36-bin histogram over 360 degrees of m times a
//    Gaussian of sigma_w = 1.5 sigma centred at the sub-pixel position, over the pixels within
//    3 sigma_w (our radius); each vote is shared linearly between its two nearest bins, and the
//    histogram is smoothed by a Gaussian of one bin (two passes of [1 2 1] / 4, circular) - both
//    ours: Lowe does not say. Every local maximum (strictly above both neighbours) of at least 80%
//    of the highest makes a keypoint (Lowe Sec. 5); its angle is the vertex of the parabola through
//    the bin and its two neighbours.
//    Samples: every p-th pixel of every p-th row, aligned on the keypoint's sample, with
//    p = max(1, round(3 sigma / 4)) - about 4 (at least 3) samples per descriptor bin width along
//    each axis, as Lowe's 16 x 16 sample array over the 4 x 4 bins (Sec. 6.1; every pixel, as
//    OpenCV takes, is up to 25 per bin and costs 3 times as much); the same for the descriptor.
// 5. Descriptor (Lowe Sec. 6.1): a 4 x 4 grid of 8-bin orientation histograms on the keypoint's
//    rotated frame; spatial bins 3 sigma wide (Lowe samples a 16 x 16 array at the keypoint's
//    scale; the bin width of 3 sigma is VLFeat's documented magnification factor, which OpenCV
//    uses too). Every sample whose rotated position falls within half a bin of the grid contributes
//    m times a Gaussian of sigma = 2 bins (half the grid width, Lowe) of its distance to the
//    keypoint, spread trilinearly over the two nearest bins in each of row, column and orientation
//    with weights 1 - d (Lowe). The 128 values are normalised to unit length, clipped at 0.2 and
//    normalised again (Lowe); then stored as OpenCV stores them: min(255, round(512 v)), integers
//    with L2 norm about 512.
//    Layout: value (r * 4 + c) * 8 + o, r the row and c the column of the rotated grid (rows along
//    the keypoint's direction turned 90 degrees clockwise on screen, columns along it), o the
//    orientation bin, 45 degrees each, counted from the keypoint's angle anticlockwise on screen.
//    That is OpenCV's layout (found by comparing with cv::SIFT::compute's output on the same
//    keypoints), so the two extractors' descriptors of a keypoint can be compared value by value
//    (the nearest-neighbour rate against OpenCV's on the same keypoints: tests/test_sift_features.cpp,
//    docs/sift.md).
// Order: by octave (-1 first), DoG image, row, column; a keypoint's orientations in the order of
// their histogram bins. max_features > 0 keeps the keypoints of largest |D(x^)| (ties: that order).
//
// Bit-identical on every x86-64 CPU: the arithmetic is +, -, *, / and sqrt of IEEE floats, in an
// order fixed by the source (no FMA contraction: the views library is compiled with
// -ffp-contract=off). exp (Gaussian taps and weights), the gradient angles, sin / cos (the
// keypoint's frame) and 2^x (scales) are the project's own (numerics/portable_math.h), not libm's
// (glibc picks FMA variants of exp, sin, cos, atan2, log and pow at run time). The blur runs 16
// lanes at a time on CPUs with AVX-512, 8 on CPUs with AVX2 (clones chosen at run time) and 4
// (SSE2) elsewhere: each lane does the same operations in the same order either way, so the choice
// changes no bit (checked under qemu's CPU models, docs/cpu.md). The extremum scan's rows run 16
// lanes at a time with AVX-512 (intrinsics, chosen at run time: comparisons, and maxima and minima
// that only comparisons read); the orientation and descriptor windows 8 samples at a time.
//
// Sources (views/): sift_features.cpp (this header's functions and the backend registry),
// sift_pyramid (step 1), sift_extractor (steps 2-4), sift_descriptor.cpp (step 5), sift_simd.h (the
// vector helpers).
//
// Conventions: the image is row-major, size x size; 0 is the background (far). Positions are in
// the view's pixel coordinates, pixel centres at integers.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::views {

/// n x 128 SIFT descriptors, one per row (row-major so a row is one contiguous descriptor).
using SiftDescriptors = Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor>;

/// The default contrast threshold (OpenCV's contrastThreshold convention: divided by the layers
/// per octave before the test, see step 3 above). Chosen when opencv was the only extractor so that
/// keypoint counts on depth views are comparable to VLFeat's defaults (peak threshold 0, edge
/// threshold 10): OpenCV's default 0.04 (about 3.4 gray levels of DoG) drops the weak interior
/// extrema that VLFeat keeps (measured on seven synthetic depth views, docs/sift.md).
inline constexpr double kDefaultContrastThreshold = 0.001;

/// The extractor (see above).
enum class SiftBackend { Canonform, OpenCV };

/// Every extractor's name, in SiftBackend's order: "canonform", "opencv".
const std::vector<std::string>& sift_backend_names();
/// The extractors built into this library, which need no other library (the view filter's
/// `sift` choices): "canonform".
const std::vector<std::string>& builtin_sift_backend_names();
/// A name of sift_backend_names() (InputError naming the choices otherwise; a removed backend's
/// name says what replaced it), and back.
SiftBackend parse_sift_backend(const std::string& name);
std::string sift_backend_name(SiftBackend backend);

/// One keypoint in the view's pixel coordinates (pixel centres at integers).
struct SiftKeypoint {
    float x = 0, y = 0;  ///< position (column, row)
    float size = 0;      ///< diameter 2 sigma in view pixels (OpenCV's KeyPoint::size convention)
    float angle = 0;     ///< orientation in degrees, [0, 360), clockwise on screen (atan2(d/drow, d/dcol))
    int octave = 0;      ///< octave of the view's scale space (-1: the approximate octave below the view's)
    float response = 0;  ///< |D(x^)| for canonform (image values in [0, 1]); OpenCV's response for opencv
};

/// Keypoints and their descriptors (row i describes keypoints[i]).
struct SiftFeatures {
    std::vector<SiftKeypoint> keypoints;
    SiftDescriptors descriptors = SiftDescriptors(0, 128);
};

/// Options of sift_features(); the thresholds mean the same for both extractors (cv::SIFT::create's
/// parameters). fine_octave and input_blur are the canonform extractor's (step 1).
struct SiftOptions {
    SiftBackend backend = SiftBackend::Canonform;           ///< the extractor
    double contrast_threshold = kDefaultContrastThreshold;  ///< t * octave_layers (>= 0), see step 3
    double edge_threshold = 10;  ///< principal-curvature ratio r (> 0; Lowe and OpenCV: 10)
    int max_features = 0;        ///< keep the strongest n keypoints; 0 = all
    double sigma = 1.6;          ///< sigma_0, the blur of each octave's first image (> 0)
    int octave_layers = 3;       ///< s, DoG images searched per octave (>= 1)
    bool fine_octave = true;     ///< canonform: the approximate octave -1 (step 1)
    double input_blur =
        0.5;  ///< canonform: the blur the view is taken to have (>= 0, < sigma / 2; Lowe's 0.5)
};

/// Registers an extractor that lives in another library (opencv_sift.h's register_opencv_sift()
/// does this for SiftBackend::OpenCV). Call before any thread extracts features.
using SiftExtractor = SiftFeatures (*)(const std::vector<float>& image, int size, const SiftOptions& options);
void register_sift_extractor(SiftBackend backend, SiftExtractor extractor);
/// Whether the backend can run in this program (built in, or registered).
bool sift_backend_available(SiftBackend backend);

/// SIFT features of a size x size image with values in [0, 1] (row-major, image.size() == size *
/// size; a depth view, or gray levels / 255): keypoints and one descriptor each, in the order above.
/// A constant image gives none. Throws InputError if size <= 0, the buffer size does not match, a
/// value is not finite, an option is out of range (negative threshold, octave_layers < 1,
/// sigma <= 0, max_features < 0, input_blur outside [0, sigma / 2)) or the backend is not available
/// in this program (the message names what is).
SiftFeatures sift_features(const std::vector<float>& image, int size, const SiftOptions& options = {});
SiftDescriptors sift_descriptors(const std::vector<float>& image, int size, const SiftOptions& options = {});

/// The same for an 8-bit image (gray level / 255).
SiftFeatures sift_features(const std::vector<std::uint8_t>& gray, int size, const SiftOptions& options = {});
SiftDescriptors sift_descriptors(const std::vector<std::uint8_t>& gray, int size,
                                 const SiftOptions& options = {});

/// The same for a depth view in [0, 1] (values clamped to it), taken as 8 bits (round(255 depth))
/// by both extractors (step 1).
SiftFeatures depth_sift_features(const std::vector<float>& depth, int size, const SiftOptions& options = {});
SiftDescriptors depth_sift_descriptors(const std::vector<float>& depth, int size,
                                       const SiftOptions& options = {});
/// The same for a depth view of size * size floats at `depth` (the caller's buffer, e.g. one kept
/// from view to view).
SiftFeatures depth_sift_features(const float* depth, int size, const SiftOptions& options = {});
SiftDescriptors depth_sift_descriptors(const float* depth, int size, const SiftOptions& options = {});

}  // namespace canonform::views
