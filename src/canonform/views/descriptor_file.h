// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the per-model view-descriptor file (CM-BOF features of one mesh).
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape retrieval
// using Clock Matching and Bag-of-Features", Machine Vision and Applications 24, 2013; Pickup et al.,
// Pattern Recognition 2015.
//
// A model is `views` depth images (66 by default, image_size x image_size). The file stores either
// the per-view bag-of-features histograms (a codebook of codebook_words words was used) or the raw
// per-view SIFT descriptors (no codebook yet: codebook_words == 0), never both.
//
// Format, version 1. All integers little endian; "u32" unsigned, "i32" two's complement; "f32"
// IEEE-754 binary32 little endian. Written atomically (temporary file + rename).
//
//   offset  size  field
//   0       4     magic "CFVD"
//   4       4     u32 version (= 1)
//   8       4     u32 L, byte length of `source`
//   12      L     source, UTF-8 (not NUL terminated), e.g. the mesh path
//   12+L    4     i32 views V (>= 1)
//   16+L    4     i32 image_size (>= 1)
//   20+L    4     i32 codebook_words W (>= 0; 0 = raw descriptors follow, > 0 = histograms follow)
//   24+L    4*V   i32 keypoints_per_view[V] (each >= 0)
//   then, if W > 0, V histogram blocks, view 0 first, each:
//           4     u32 nnz (number of non-zero words, <= W)
//           8*nnz nnz x (i32 word, f32 count): words strictly increasing in [0, W), counts finite
//                 and > 0, summing exactly to keypoints_per_view[view] (counts are integers)
//   or, if W == 0, V descriptor blocks, view 0 first, each:
//           4     u32 rows (= keypoints_per_view[view])
//           4*128*rows  f32, row-major (descriptor 0's 128 values first), all finite
//   nothing after the last block.
//
// read_descriptor() checks every field above and throws InputError naming the file and the
// problem (cannot open, wrong magic, unsupported version, truncated, trailing bytes, inconsistent
// counts, out-of-range word, non-finite value). write_descriptor() applies the same checks first,
// so a file it writes can always be read back.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/views/bag_of_features.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::views {

/// The descriptors of one model (see the format above).
struct ModelDescriptor {
    int version = 1;                    ///< format version (only 1 exists)
    std::string source;                 ///< where the model came from (mesh path), free text
    int views = 66;                     ///< number of views V
    int image_size = 256;               ///< depth image side in pixels
    std::vector<Histogram> histograms;  ///< V histograms if a codebook was used, else empty
    int codebook_words = 0;             ///< size of that codebook; 0 = raw descriptors
    std::vector<Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor>>
        raw;                              ///< V matrices if no codebook, else empty
    std::vector<int> keypoints_per_view;  ///< V keypoint counts
};

/// Writes `d` to `path` (format above, atomic). Throws InputError if `d` is inconsistent or the
/// file cannot be written.
void write_descriptor(const std::string& path, const ModelDescriptor& d);

/// Reads and validates a file written by write_descriptor() (InputError naming the file and the
/// cause: missing, a folder, unreadable, or any of the problems above).
ModelDescriptor read_descriptor(const std::string& path);

/// Parses and validates the bytes of a descriptor file; `where` starts every message.
ModelDescriptor parse_descriptor(const std::string& bytes, const std::string& where);

}  // namespace canonform::views
