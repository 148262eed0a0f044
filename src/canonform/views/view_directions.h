// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the 66 view directions of Lian et al.'s view-based descriptor (CM-BOF) and the 24
// rotations of the cube used by its clock matching.
//
// Reference: Z. Lian, A. Godil, X. Sun, J. Xiao, "CM-BOF: visual similarity-based 3D shape
// retrieval using Clock Matching and Bag-of-Features", Machine Vision and Applications 2013;
// Pickup et al., Pattern Recognition 2015, Section 3 (they plug canonical forms into CM-BOF).
//
// - Views: the vertices of an octahedron (+-x, +-y, +-z) subdivided twice. Each subdivision splits
//   every triangle in four at its edge midpoints, which are pushed onto the unit sphere before the
//   next subdivision: 6 -> 18 -> 66 vertices. The set is invariant under the 48 signed axis
//   permutations, so the 24 rotations of the cube permute the views (clock matching relies on it).
// - Order: ascending lexicographic order of (x, y, z), each coordinate rounded to 1e-9 before
//   comparing (so the order does not depend on rounding noise). Index 0 is (-1, 0, 0), index 65 is
//   (1, 0, 0). The order is part of the interface: descriptors store views by this index.
// - Rotations: signed permutation matrices with determinant +1, R(i, p[i]) = s[i]. Enumerated with
//   the permutation p of (0, 1, 2) in lexicographic order (outer loop) and the sign pattern s in
//   binary order, + before - per axis, first axis slowest (inner loop); those with det -1 are
//   skipped. Index 0 is the identity.
#pragma once

#include "canonform/common/errors.h"

#include <Eigen/Core>

#include <vector>

namespace canonform::views {

/// Number of view directions (vertices of the twice subdivided octahedron).
constexpr int kNumViews = 66;
/// Number of rotations of the cube (proper signed axis permutations).
constexpr int kNumCubeRotations = 24;

/// The 66 unit view directions in the documented order (see the file comment). Each is the
/// position of a camera on the unit sphere, looking at the origin.
std::vector<Eigen::Vector3d> view_directions();

/// The 24 rotations of the cube (signed permutation matrices, det +1), identity first, in the
/// documented order.
std::vector<Eigen::Matrix3d> cube_rotations();

/// map[r][i] = j such that view_directions()[j] == cube_rotations()[r] * view_directions()[i]
/// (to 1e-9). 24 x 66; every row is a permutation of 0..65 and row 0 is the identity. Throws
/// NumericalError if some image is not a view direction (cannot happen for the documented sets).
std::vector<std::vector<int>> rotation_view_maps();

/// opposite[i] = j such that view_directions()[j] == -view_directions()[i] exactly (the set is
/// symmetric about the origin and built symmetrically: 33 antipodal pairs; render_depth_pair
/// renders a pair in one pass). Throws NumericalError if some direction has no exact opposite.
std::vector<int> opposite_views();

}  // namespace canonform::views
