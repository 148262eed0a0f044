// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: a small headless software rasteriser for pictures of meshes.
//
// Orthographic projection, z-buffer, two-sided Lambert shading of flat triangles with per-vertex
// colours interpolated across each triangle; markers for points (drawn solid where visible,
// as rings where hidden). Pure Eigen + std: no X server, no GL context, deterministic.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace canonform::render {

/// An RGB image with a depth buffer (larger depth = closer to the viewer).
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  ///< width * height * 3, row-major from the top-left
    std::vector<float> depth;       ///< width * height, -inf where empty
    Image(int w, int h, Eigen::Vector3d background = Eigen::Vector3d::Ones());
};

/// Camera: rows of R are the screen's right, up and toward-viewer axes (world coordinates).
struct View {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    double scale = 1;                                  ///< pixels per world unit
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();  ///< pixel position of the world origin
};

/// A view looking along the mesh's smallest principal axis, with the largest one up, that fits
/// V into a width x height image with `margin` pixels around.
View fit_view(const Eigen::MatrixXd& V, int width, int height, int margin = 12);

/// Rasterises the mesh (V #V x 3, F #F x 3) with per-vertex colours C (#V x 3 in [0, 1]).
void draw_mesh(Image& img, const View& view, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::MatrixXd& C);

/// Draws a disc of `radius` pixels at each point P (#P x 3): solid `color` where the point is
/// visible (within `tolerance` world units of the depth buffer), a ring where it is hidden.
void draw_points(Image& img, const View& view, const Eigen::MatrixXd& P, const Eigen::Vector3d& color,
                 int radius = 4, double tolerance = 0.02);

/// A blue-cyan-green-yellow-red ramp for t in [0, 1] (MeshLab's quality colouring).
Eigen::Vector3d ramp(double t);

}  // namespace canonform::render
