// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the cotangent Laplacian of a triangle mesh.
//
// Reference: U. Pinkall and K. Polthier, "Computing discrete minimal surfaces and their
// conjugates", Experimental Mathematics 2(1), 1993; used as the discrete Laplace-Beltrami
// operator L of eq. (7) in Pickup et al., "Euclidean-distance-based canonical forms for non-rigid
// 3D shape retrieval", Pattern Recognition 2015 (ref. [40] there).
//
// Convention: L = D - W, with W_ij = (cot a_ij + cot b_ij) / 2 for an edge (i, j) whose opposite
// corner angles are a_ij and b_ij (one of them for a boundary edge), and D = diag(row sums of W).
// L is symmetric, L 1 = 0, and positive semi-definite where all weights are positive. It is the
// *integrated* operator (no division by vertex areas): (L u)_i ~ -A_i (Laplace-Beltrami u)(x_i).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace canonform::surface {

/// Cotangent Laplacian L = D - W of the mesh (V #V x 3, F #F x 3); #V x #V, symmetric, compressed.
/// `threads` (0: every core) share the work on large meshes; the values do not depend on them.
Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            int threads = 0);

}  // namespace canonform::surface
