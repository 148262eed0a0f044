// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the `opencv` SIFT extractor - OpenCV's cv::SIFT through its public API - in a library of
// its own (canonform::views_opencv), so that only the programs that want it link OpenCV: the
// canonform tool, the tests and the benchmarks. The view filter does not.
//
// OpenCV's SIFT (features2d, OpenCV >= 4.4) on the view as 8 bits (round(255 v)), with the options
// of SiftOptions passed to cv::SIFT::create (nfeatures, nOctaveLayers, contrastThreshold,
// edgeThreshold, sigma). OpenCV doubles the image before its first octave (octave -1), upsampling
// with half-pixel centres: doubled pixel j is view position j / 2 - 0.25, but OpenCV reports j / 2,
// so its positions are 0.25 pixel right of and below the feature; they are moved back here, so that
// both extractors report positions in the view's pixel coordinates. OpenCV packs a keypoint's
// octave into the low byte of KeyPoint::octave (a signed 8-bit value), its layer into the next.
// Descriptors: OpenCV's (integer values 0-255, L2 norm about 512), in OpenCV's order.
#pragma once

#include "canonform/views/sift_features.h"

namespace canonform::views {

/// Registers the extractor for SiftBackend::OpenCV (sift_features.h). Idempotent.
void register_opencv_sift();

/// OpenCV's SIFT of an image with values in [0, 1] (seen as 8 bits), see above.
SiftFeatures opencv_sift_features(const std::vector<float>& image, int size, const SiftOptions& options = {});

/// OpenCV's descriptors (cv::SIFT::compute) of given keypoints of an image with values in [0, 1]
/// (seen as 8 bits): each keypoint handed to OpenCV with its size, angle and octave, and the
/// layer of OpenCV's pyramid nearest its scale (OpenCV describes a keypoint on the Gaussian image of
/// the octave and layer it carries). OpenCV builds its pyramid from the smallest octave given
/// (-1: the doubled image, whose 0.25-pixel offset is added to every position then). Row i
/// describes keypoints[i]; OpenCV must keep every keypoint (NumericalError otherwise).
SiftDescriptors opencv_descriptors_at(const std::vector<float>& image, int size,
                                      const std::vector<SiftKeypoint>& keypoints,
                                      const SiftOptions& options = {});

}  // namespace canonform::views
