// SPDX-License-Identifier: GPL-3.0-or-later
#include "view_filter_table.h"

#include "canonform/views/sift_features.h"

namespace canonform::plugin {

const std::vector<FilterSpec>& view_filter_table() {
    static const std::vector<FilterSpec> table = [] {
        using K = ParamKind;
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
                      {"sift", K::Enum, 5, "SIFT extractor",
                       "opencv: OpenCV's SIFT on the 8-bit view; opencv-half: the same with its first "
                       "octave at the view's resolution (faster); vlfeat: VLFeat's SIFT at its defaults on the "
                       "float depth; opencv-fast: opencv-half's keypoints with descriptors of the full view; "
                       "opencv-octave0: opencv's keypoints from octave 0 up, found without its doubled image; "
                       "opencv-octave0-fine (default): the same plus an approximate octave -1 on the view itself. A "
                       "codebook must come from the same extractor.",
                       views::sift_backend_names()}},
                     kNothing, kNothing});
        return t;
    }();
    return table;
}

}  // namespace canonform::plugin
