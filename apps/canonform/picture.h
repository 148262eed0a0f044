// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the side-by-side picture of a mesh, its feature points and its canonical form.
#pragma once

#include "canonform/io/mesh_io.h"

#include <Eigen/Core>

#include <string>

namespace canonform::views {
struct ViewSet;
}

namespace canonform {

/// What the picture shows; empty members are left out.
struct PictureInputs {
    Mesh mesh;                          ///< the input mesh
    Eigen::VectorXd mesh_quality;       ///< colour of the mesh (e.g. conformal factor), or empty
    Eigen::MatrixXd points;             ///< feature points (#P x 3), or empty
    Mesh canonical;                     ///< canonical form (same vertex order as mesh), or empty
    Eigen::VectorXd canonical_quality;  ///< colour of the canonical form, or empty
};

/// Refuses a mesh the picture cannot draw, naming `path` and the cause: no vertices, no faces (a
/// point cloud), NaN or infinite coordinates, all vertices at one point, or a quality with NaN or
/// infinite values.
void check_drawable(const std::string& path, const Mesh& m, const Eigen::VectorXd& quality);

/// Refuses feature points that cannot be drawn (none, or NaN or infinite coordinates).
void check_points(const std::string& path, const Eigen::MatrixXd& P);

/// Renders up to three labelled panels of `panel` x `panel` pixels (mesh coloured by quality;
/// mesh with the feature points; canonical form with the feature points) into a PNG at `path`,
/// written atomically. Needs no X server (Qt's offscreen platform is used for the labels).
void write_picture(const std::string& path, const PictureInputs& in, int panel);

/// The 66 depth views of `views` as PNGs in `dir` (view_00.png ... view_65.png) and a labelled
/// contact sheet of them (contact_sheet.png): the `views` command's pictures.
void write_view_images(const std::string& dir, const views::ViewSet& views);

}  // namespace canonform
