// SPDX-License-Identifier: GPL-3.0-or-later
#include "view_filter_table.h"

#include "canonform/views/sift_features.h"

#include <algorithm>

namespace canonform::meshlab {

const std::vector<FilterSpec>& view_filter_table() {
    static const std::vector<FilterSpec> table = [] {
        using K = ParamKind;
        // The choices are the extractors built into the views library; the default is the library's.
        const auto& sift_names = views::builtin_sift_backend_names();
        const double sift_default = static_cast<double>(
            std::find(sift_names.begin(), sift_names.end(), views::sift_backend_name(views::SiftOptions{}.backend)) -
            sift_names.begin());
        std::vector<FilterSpec> t;
        t.push_back({int(ViewFilterId::DepthViewDescriptor), "Depth view descriptor", "compute_depth_view_descriptor",
                     "depth_view_descriptor.mlx", FilterKind::Measure,
                     prose(R"(Computes the view-based shape descriptor of Lian et al. (CM-BOF) that Pickup et
                     al. 2015 plug their canonical forms into: the mesh is pose-normalised (PCA and
                     rectilinearity), rendered as 66 orthographic depth images from the vertices of a
                     twice-subdivided octahedron, and SIFT features are extracted from each view. With a
                     codebook file the descriptor holds one bag-of-features histogram per view, else the raw
                     SIFT features. Compare descriptors with <i>canonform distance</i> (clock
                     matching).<br><br>Z. Lian, A. Godil, X. Sun, J. Xiao, <b>"CM-BOF: visual similarity-based
                     3D shape retrieval using Clock Matching and Bag-of-Features"</b>, Machine Vision and
                     Applications, 2013.)"),
                     {{"output_file", K::String, 0, "Descriptor file",
                       "Where to write the descriptor (canonform's versioned .cfvd format); empty: write no file "
                       "(pymeshlab returns the descriptor as a vector either way).", {}, "descriptor.cfvd"},
                      {"codebook_file", K::String, 0, "Codebook file (optional)",
                       "A codebook from 'canonform codebook'; empty: store the raw SIFT features.", {}, ""},
                      {"image_size", K::Int, 256, "Image size (pixels)", "Side of each depth image.", {}},
                      {"views_folder", K::String, 0, "Write the views to (optional)",
                       "A folder for the 66 depth images as PNG; empty: do not write them.", {}, ""},
                      {"seed", K::Int, 0, "Random seed", "Seed of the rectilinearity restarts.", {}},
                      {"sift", K::Enum, sift_default, "SIFT extractor",
                       "canonform (default): the project's own SIFT (Lowe 2004) on the depth view, at the "
                       "view's resolution with an approximate finer octave. A codebook must come from the same "
                       "extractor (the canonform tool also offers OpenCV's SIFT, `--sift opencv`).",
                       views::builtin_sift_backend_names()}},
                     kNothing, kNothing});
        return t;
    }();
    return table;
}

}  // namespace canonform::meshlab
