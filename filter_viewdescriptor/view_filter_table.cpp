// SPDX-License-Identifier: GPL-3.0-or-later
#include "view_filter_table.h"

#include "canonform/views/view_parameters.h"

namespace canonform::meshlab {

namespace {

// The parameters only this filter has (its files); the others are the library's definitions.
Parameter output_file_parameter() {
    return Parameter::text("output_file")
        .default_value("descriptor.cfvd")
        .label("Descriptor file")
        .help(
            "where to write the descriptor (canonform's versioned .cfvd format); empty: write no file "
            "(pymeshlab "
            "returns the descriptor as a vector either way)");
}
Parameter codebook_file_parameter() {
    return Parameter::text("codebook_file")
        .label("Codebook file (optional)")
        .help("a codebook from 'canonform codebook'; empty: store the raw SIFT features");
}
Parameter views_folder_parameter() {
    return Parameter::text("views_folder")
        .label("Write the views to (optional)")
        .help("a folder for the 66 depth images as PNG; empty: do not write them");
}

}  // namespace

const std::vector<FilterSpec>& view_filter_table() {
    static const std::vector<FilterSpec> table = [] {
        const std::vector<Parameter> views =
            views::view_descriptor_parameters({}, views::builtin_sift_backend_names()).parameters();
        const auto view = [&views](const char* name) { return *find_parameter(views, name); };
        std::vector<FilterSpec> t;
        t.push_back(FilterSpec("Depth view descriptor", "compute_depth_view_descriptor", FilterKind::Measure)
                        .with_info(prose(
                            R"(Computes the view-based shape descriptor of Lian et al. (CM-BOF) that Pickup et
                     al. 2015 plug their canonical forms into: the mesh is pose-normalised (PCA and
                     rectilinearity), rendered as 66 orthographic depth images from the vertices of a
                     twice-subdivided octahedron, and SIFT features are extracted from each view. With a
                     codebook file the descriptor holds one bag-of-features histogram per view, else the raw
                     SIFT features. Compare descriptors with <i>canonform distance</i> (clock
                     matching).<br><br>Z. Lian, A. Godil, X. Sun, J. Xiao, <b>"CM-BOF: visual similarity-based
                     3D shape retrieval using Clock Matching and Bag-of-Features"</b>, Machine Vision and
                     Applications, 2013.)"))
                        .with_params({output_file_parameter(), codebook_file_parameter(), view("image_size"),
                                      views_folder_parameter(), view("seed"), view("sift")})
                        .with_needs(kNothing)
                        .with_changes(kNothing));
        number_filters(t);
        return t;
    }();
    return table;
}

}  // namespace canonform::meshlab
