// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the discrete conformal factor of a triangle mesh.
//
// Reference: Pickup, Sun, Rosin, Martin, "Euclidean-distance-based canonical forms for non-rigid
// 3D shape retrieval", Pattern Recognition 2015, Section 4, eqs. (7)-(9); after M. Ben-Chen and
// C. Gotsman, "Characterizing shape using conformal factors", 3DOR 2008.
//
//   (7)  L phi = K^T - K^0
//   (8)  K^0_v = angle deficit (2 pi, or pi on the boundary, minus the corner angles at v)
//   (9)  K^T_v = (sum_i K^0_i) * A_v / A_total,  A_v = one third of the one-ring area
//
// Sign convention (the paper leaves it implicit): we solve (D - W) phi = K^0 - K^T with the
// cotangent Laplacian D - W of cotan_laplacian.h, i.e. eq. (7) with L = W - D, the negative
// semi-definite Laplace-Beltrami operator. With this sign the conformal factor is largest at the
// extremities of the shape (limb tips), as the paper's Figs. 3 and 4 show and as feature-point
// selection needs; the opposite sign would put the maxima on the body.
//
// The system is singular (constants are in the kernel) and consistent (sum K^0 = sum K^T): we pin
// vertex 0, solve the reduced system, then shift phi to area-weighted mean zero. The solve is a
// sparse Cholesky factorisation (sparse_cholesky.h) below kMultigridFrom vertices and
// AMG-preconditioned CG (algebraic_multigrid.h, relative residual 1e-10) from there, where the
// factorisation's superlinear cost dominates (docs/benchmarks.md). The mesh is
// first scaled so that the largest vertex distance to the centroid is 1, as in the paper (phi
// itself is scale invariant). The solver status and the relative residual are checked
// (NumericalError otherwise).
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/parameters.h"
#include "canonform/numerics/algebraic_multigrid.h"

#include <Eigen/Core>

#include <vector>

namespace canonform::surface {

/// Options of conformal_factor().
struct ConformalFactorOptions {
    double residual_tolerance = 1e-6;  ///< max ||L phi - rhs||_inf / ||rhs||_inf accepted
    numerics::LinearSolver linear_solver = numerics::LinearSolver::Auto;  ///< how eq. (7) is solved
    int threads = 0;       ///< multigrid: threads of its large sweeps (0: every core; no effect on results)
    bool validate = true;  ///< run validate_mesh() first (InputError on bad input)
    /// Boundary vertices (#V flags, MeshReport::boundary) when the caller validated the mesh
    /// itself; empty = found from F (or taken from validate_mesh's report).
    std::vector<bool> boundary;
    ProgressFn progress;  ///< optional progress callback
};

/// Result of conformal_factor().
struct ConformalFactorResult {
    Eigen::VectorXd raw;         ///< phi of eq. (7), #V, area-weighted mean zero (dimensionless)
    Eigen::VectorXd normalized;  ///< (phi - min) / (max - min), in [0, 1]; all 0.5 if phi is constant
    Eigen::VectorXd curvature;   ///< K^0 (#V, radians)
    Eigen::VectorXd target;      ///< K^T (#V, radians)
    double residual = 0;         ///< relative residual of the solve
    /// Fill-reducing ordering of the direct solver's factorisation of the Laplacian with vertex 0
    /// pinned (#V - 1 entries; entry k = vertex ordering[k] + 1 eliminated k-th); empty with the
    /// multigrid solver. The Euclidean canonical form reuses it for SMACOF's
    /// V, which lives on the same edges.
    std::vector<int> ordering;
};

/// The `normalize` parameter: store ConformalFactorResult::normalized (default) or raw (the
/// conformal factor filter's parameter; the tool's --no-normalize, also --raw).
Parameter normalize_parameter();

/// Conformal factor of the mesh (V #V x 3, F #F x 3). Throws InputError on bad input,
/// NumericalError if the factorisation fails or the residual is above tolerance.
ConformalFactorResult conformal_factor(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const ConformalFactorOptions& options = {});

/// Translates V to its vertex centroid and scales it so the largest vertex distance to the
/// centroid is 1 (paper, Section 4). Returns the scaled copy; *centroid and *scale (the factor
/// that was divided by) let the caller undo it: V = scaled * scale + centroid.
Eigen::MatrixXd normalize_scale(const Eigen::MatrixXd& V, Eigen::RowVector3d* centroid = nullptr,
                                double* scale = nullptr);

}  // namespace canonform::surface
