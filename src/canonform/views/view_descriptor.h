// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the view-based descriptor of Lian et al. (CM-BOF), end to end for one mesh.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 2013; the
// view-based retrieval Pickup et al. 2015 (Section 3.2) plug their canonical forms into.
//
//   pose normalisation (pose_normalization.h) -> 66 orthographic depth views
//   (view_directions.h, depth_render.h) -> SIFT per view (sift_features.h) -> with a codebook
//   (codebook.h), one bag-of-features histogram per view (bag_of_features.h).
// Two models are compared by clock matching (bag_of_features.h, with rotation_view_maps()).
#pragma once

#include "canonform/views/bag_of_features.h"
#include "canonform/views/codebook.h"
#include "canonform/views/depth_render.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/pose_normalization.h"
#include "canonform/views/sift_features.h"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace canonform::views {

/// Options of compute_views().
struct ViewDescriptorOptions {
    int image_size = 256;     ///< pixels per side of each depth view
    PoseOptions pose;         ///< rectilinearity restarts and seed
    SiftOptions sift;         ///< SIFT thresholds
    bool keep_images = true;  ///< ViewSet::images filled (else empty: the features alone, less memory)
};

/// The 66 views of a mesh: its pose, the depth images and their SIFT descriptors.
struct ViewSet {
    PoseNormalization pose;
    std::vector<DepthImage> images;  ///< 66, in the order of view_directions() (none without keep_images)
    std::vector<SiftDescriptors> features;  ///< 66, n_i x 128 each (n_i may be 0)
    /// Keypoints per view.
    std::vector<int> keypoint_counts() const;
};

/// Validates the mesh (InputError: empty, no faces, non-finite, degenerate faces, non-manifold
/// edges - several components are allowed), normalises its pose and computes the 66 views.
ViewSet compute_views(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                      const ViewDescriptorOptions& options = {});

/// The 66 depth images of a posed mesh (X: #V x 3, in the unit ball), in the order of
/// view_directions(); each of the 33 antipodal pairs rasterised in one pass (render_depth_pair).
std::vector<DepthImage> render_views(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, int size = 256);

/// One bag-of-features histogram per view (a view without keypoints gives an empty histogram).
std::vector<Histogram> view_histograms(const std::vector<SiftDescriptors>& features,
                                       const Codebook& codebook);
inline std::vector<Histogram> view_histograms(const ViewSet& views, const Codebook& codebook) {
    return view_histograms(views.features, codebook);
}

/// The descriptor file's contents for a model's view features (one per view): with a codebook its
/// histograms, without one the raw SIFT features. `source` names the model (free text).
ModelDescriptor make_descriptor(const std::vector<SiftDescriptors>& features, const Codebook* codebook,
                                const std::string& source, int image_size = 256);

/// A model's SIFT descriptors over all its views (its rows in the stack below).
std::size_t feature_rows(const std::vector<SiftDescriptors>& views);

/// The SIFT descriptors of many views stacked into one matrix (the training set of a codebook).
SiftDescriptors stack_features(const std::vector<const std::vector<SiftDescriptors>*>& models);

/// Rows `rows` of that stack - the features of models 0 .. counts.size() - 1, view after view,
/// model after model - in the order of `rows`, without forming the stack (a codebook's sample,
/// Codebook::training_rows(), of a large collection). features(g) is called once per model holding
/// a wanted row, in model order; what it returns is read before the next call. counts[g]: model
/// g's rows. InputError if a model's features have another number of rows or a row lies outside
/// the stack.
SiftDescriptors stacked_rows(const std::vector<std::size_t>& counts, const std::vector<int>& rows,
                             const std::function<const std::vector<SiftDescriptors>&(std::size_t)>& features);

}  // namespace canonform::views
