// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: orthographic depth images of a triangle mesh, as captured by the view-based
// descriptor of Lian et al. (CM-BOF): 66 cameras on the unit sphere looking at the origin, one
// 256 x 256 depth image each, background = far.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 2013;
// Pickup et al., Pattern Recognition 2015, Section 3, Fig. 2(d).
//
// Camera for a unit direction d (the camera sits at d and looks along -d):
// - up    u = the world axis e_k least aligned with d (smallest |d_k|; ties within 1e-9 go to the
//             lowest k), orthogonalised against d and normalised: u = normalize(e_k - (e_k.d) d);
// - right r = u x d (so that r x u = d: a right-handed camera frame looking along -d).
// The image spans [-1, 1] x [-1, 1] in (r, u) coordinates (the mesh is assumed to lie in the unit
// ball, e.g. after normalize_pose). Pixel (row, col), row 0 at the top, has its centre at
//   x = -1 + (col + 0.5) * 2 / size   (along r),   y = 1 - (row + 0.5) * 2 / size   (along u).
// Depth of a surface point p: (1 + p.d) / 2, clamped to [0, 1]: 1 = the nearest possible point,
// 0 = the farthest possible point and the background.
//
// Rasterisation: every triangle (both orientations, no back-face culling) is sampled at the pixel
// centres; a centre on an edge is covered (the edge function of a shared edge is evaluated with its
// endpoints in a canonical order, so neighbouring triangles leave no cracks); depth is interpolated
// linearly (exact for an orthographic camera); the z-buffer keeps the largest depth. Triangles whose
// projection has (near) zero area are skipped. The result does not depend on the triangle order.
//
// Opposite views in one pass (render_depth_pair; ours, for speed: the 66 directions are 33
// antipodal pairs). The camera of -d has the same up vector and the opposite right vector, so its
// pixel (row, col) sees along the same line as d's pixel (row, size - 1 - col), and its depth of a
// point is 1 - the depth d's camera gives it: its image is, mirrored, the largest 1 - depth over
// the fragments of d's pass (the farthest surface). In exact arithmetic this is render_depth(-d);
// in floating point the pixel centres on a triangle's edge and the last bits of a depth may differ
// (the edge functions and depths are evaluated in d's coordinates, not -d's).
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace canonform::views {

/// A square depth image.
struct DepthImage {
    int size = 0;              ///< width = height in pixels
    std::vector<float> depth;  ///< size*size, row-major, row 0 at the top; in [0, 1], 1 = nearest
                               ///< possible point (p.d = 1), 0 = background / farthest (p.d = -1)
    /// 8-bit version: round(255 * depth), row-major like `depth`.
    std::vector<std::uint8_t> gray() const;
    /// depth at (row, col).
    float at(int row, int col) const { return depth[static_cast<size_t>(row) * size + col]; }
};

/// The camera frame of a view direction (see the file comment): rows r (image right), u (image
/// up), d (towards the camera). A rotation (det +1).
Eigen::Matrix3d camera_frame(const Eigen::Vector3d& direction);

/// Renders the depth image of the mesh (V: #V x 3, F: #F x 3, 0-based) seen from the unit
/// direction `direction` (normalised here; must be non-zero), size x size pixels (2..8192).
/// Throws InputError on a zero or non-finite direction, a bad size, non-finite vertices or face
/// indices out of range. An empty F gives an all-zero image.
DepthImage render_depth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& direction,
                        int size = 256);

/// The depth images seen from `direction` and from its opposite, rasterised in one pass (see the
/// file comment): {view of direction, view of -direction}. Same arguments and errors as
/// render_depth; the first image is render_depth's exactly.
std::array<DepthImage, 2> render_depth_pair(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const Eigen::Vector3d& direction, int size = 256);

/// Many renders of one mesh: the mesh and the size are checked once, on construction (render_depth's
/// errors), instead of once per render (compute_views() renders 33 pairs). V and F are referenced,
/// not copied: they must outlive the renderer and stay unchanged.
class DepthRenderer {
public:
    DepthRenderer(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int size);
    /// render_depth_pair(V, F, direction, size) into the caller's buffers of size * size floats
    /// each (overwritten): the same two images, without allocating per pair (compute_views()
    /// reuses its buffers). Throws InputError on a zero or non-finite direction.
    void pair_into(const Eigen::Vector3d& direction, float* front, float* back) const;

private:
    const Eigen::MatrixXd& V_;
    const Eigen::MatrixXi& F_;
    int size_;
};

}  // namespace canonform::views
