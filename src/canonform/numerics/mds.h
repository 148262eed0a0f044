// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: multidimensional scaling of a full distance matrix (least squares, classical, landmark).
//
// Reference: Pickup et al., Pattern Recognition 2015 (the comparison against Elad-Kimmel canonical
// forms computed with least-squares, classical and fast MDS); A. Elad and R. Kimmel, "On bending
// invariant signatures for surfaces", IEEE TPAMI 2003; J. de Leeuw, "Applications of convex
// analysis to multidimensional scaling", 1977 (SMACOF); W. S. Torgerson, "Multidimensional
// scaling: I. Theory and method", Psychometrika 1952 (classical MDS); V. de Silva and
// J. B. Tenenbaum, "Sparse multidimensional scaling using landmark points", Stanford tech. report
// 2004 (landmark MDS).
//
// All three embed a symmetric #N x #N distance matrix D (zero diagonal) into R^dim and return the
// #N x dim configuration X centred at the origin. X is determined only up to an isometry
// (rotation, translation and reflection).
//
// 1. least_squares_mds: SMACOF with all pairs and unit weights (Elad-Kimmel).
//      S(X) = sum_{i<j} (D_ij - d_ij(X))^2,   X_k = V^+ B(X_{k-1}) X_{k-1}
//    With w_ij = 1, V = N I - 1 1^T = N J, V^+ = J / N and 1^T B = 0, so the Guttman transform is
//    exactly X_k = B(X_{k-1}) X_{k-1} / N: no linear solve. (B X)_i = sum_{j != i} (D_ij / d_ij)
//    (x_i - x_j) is accumulated pair by pair over the lower triangle (column i of D from row i+1,
//    contiguous in memory) together with S(X), O(N^2 dim) per iteration without forming B; rows
//    are split between workers (parallel_for; equal numbers of pairs, one private accumulator each).
//    Start: classical MDS (default) or a given X0. Stop when (S_{k-1} - S_k) / S_{k-1} <
//    tolerance or after max_iterations. Stress never increases across a Guttman step (tested).
//    If the classical start has a (numerically) zero column - B has fewer than dim positive
//    eigenvalues - that column is filled with seeded noise of size 1e-4 * the configuration's
//    scale, because a Guttman step can never leave the subspace spanned by the start's columns.
//
// 2. classical_mds (Torgerson): B = -1/2 J D^(2) J, J = I - 1 1^T / N (D^(2): entrywise
//    squares); X = the top-dim eigenvectors of B scaled by sqrt(max(lambda, 0)). The top
//    eigenpairs come from block subspace iteration (never a dense O(N^3) eigensolver): Q is
//    N x min(N, dim + 4) orthonormal, each iteration applies B once (B Q = -1/2 J (D^(2) (J Q)),
//    D^(2) squared on the fly, O(N^2 (dim + 4)), no N x N temporary), does a Rayleigh-Ritz step,
//    and re-orthonormalises (Householder QR). Converged when every wanted Ritz pair has
//    ||B q - theta q|| < eigen_tolerance * max(|theta|, 1e-6 * |theta_max|); otherwise
//    NumericalError after eigen_max_iterations. Subspace iteration finds the eigenvalues of largest
//    *magnitude*; when the block holds large negative eigenvalues (strongly non-Euclidean D) a
//    wanted positive one could be missed, so in that case the iteration is restarted on
//    B + sigma I (sigma = -most negative Ritz value), whose top eigenvectors are B's top ones.
//
// 3. landmark_mds: the "fast MDS" we use is Landmark MDS (de Silva and Tenenbaum 2004): cheap
//    (O(N L dim) after an O(L^3) eigenproblem on the L x L landmark block), deterministic given the
//    seed, exact for Euclidean input, and the standard fast alternative to classical MDS; the other
//    candidate, Faloutsos-Lin FastMap, is also O(N k) but recovers Euclidean configurations only
//    approximately (pivot-dependent projections). Landmarks are chosen by farthest-point (max-min)
//    sampling on D from a seeded random first point. Default L = clamp(3 ceil(sqrt(N)), dim+1, N)
//    (45 for N = 200, 135 for N = 2000), MdsOptions::landmarks overrides. Classical MDS on the
//    landmark block gives the landmarks' coordinates L_k = sqrt(lambda_k) v_k; every point a is
//    then placed by distance-based triangulation x_a = -1/2 L^# (delta_a - delta_mean), delta_a its
//    squared distances to the landmarks, L^# rows v_k^T / sqrt(lambda_k) (rows with lambda_k <=
//    1e-10 lambda_1 are zero). The result is finally centred.
//
// Input checks (check_input, O(N^2), one pass plus a blocked symmetry pass): square, N >= dim + 1,
// finite, non-negative, |D_ii| and |D_ij - D_ji| at most symmetry_tolerance * max D. Within that
// tolerance only the lower triangle D(j, i), j > i, is used by the stress and SMACOF; classical MDS
// uses whole columns.
// Results are the same bits for every `threads` and on every x86-64 CPU: the all-pairs pass sums
// 16 fixed row blocks in order (threads only pick blocks), and the products with a long inner
// dimension are summed in fixed blocks of 64 (Eigen's own blocking follows the L1 cache size that
// CPUID reports).
#pragma once

#include "canonform/common/errors.h"
#include "canonform/numerics/smacof.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace canonform::numerics {

enum class MdsMethod { LeastSquares, Classical, Landmark };

/// Options of the MDS solvers (fields a method does not use are ignored).
struct MdsOptions {
    int dim = 3;  ///< embedding dimension (>= 1)
    /// Least squares: its SMACOF iteration (tolerance, cap, acceleration, history); its progress
    /// is not called: `progress` below reports the whole run.
    SmacofOptions smacof = SmacofOptions().with_max_iterations(500);
    int landmarks = 0;                 ///< landmark MDS: L in [dim+1, N]; 0 = clamp(3 ceil(sqrt N), dim+1, N)
    std::uint64_t seed = 0;            ///< subspace-iteration start, first landmark, degenerate-start noise
    int threads = 0;                   ///< worker threads; 0 = every hardware thread (thread_count())
    double eigen_tolerance = 1e-8;     ///< classical: relative Ritz residual for convergence
    int eigen_max_iterations = 1000;   ///< classical: subspace-iteration cap (NumericalError beyond)
    double symmetry_tolerance = 1e-9;  ///< relative to max D: allowed |D_ij - D_ji| and |D_ii|
    bool check_input = true;           ///< full O(N^2) validation of D (shape is always checked)
    bool compute_stress = true;        ///< classical/landmark: fill initial/final_stress (O(N^2))
    ProgressFn progress;               ///< called every few iterations; false cancels (Cancelled)
};

/// The parameters of MdsOptions a user sets (its SMACOF iteration's: smacof_parameters()), with
/// their defaults from `defaults`.
ParameterSet<MdsOptions> mds_parameters(const MdsOptions& defaults = {});

/// Result of the MDS solvers: X (#N x dim, centred at the origin) and the statistics of
/// SmacofResult - SMACOF's for least squares; classical: iterations = subspace iterations,
/// converged = true, the stresses S(X) (NaN if not computed); landmark: iterations 0,
/// converged = true, the stresses likewise.
struct MdsResult : SmacofResult {
    Eigen::VectorXd
        eigenvalues;             ///< classical: top dim eigenvalues of B; landmark: of the landmark block's B
    std::vector<int> landmarks;  ///< landmark MDS: the chosen landmark indices, in order of choice
};

/// Classical (Torgerson) MDS via subspace iteration. InputError on bad D, NumericalError if the
/// eigenpairs do not converge within eigen_max_iterations.
MdsResult classical_mds(const Eigen::MatrixXd& D, const MdsOptions& options = {});

/// Landmark MDS (de Silva-Tenenbaum). InputError on bad D or landmark count.
MdsResult landmark_mds(const Eigen::MatrixXd& D, const MdsOptions& options = {});

/// Least-squares MDS (SMACOF, all pairs, unit weights) from X0 (#N x dim) or, if X0 is null,
/// from classical MDS. InputError on bad D or X0, NumericalError on non-finite iterates.
MdsResult least_squares_mds(const Eigen::MatrixXd& D, const MdsOptions& options = {},
                            const Eigen::MatrixXd* X0 = nullptr);

/// Dispatches to one of the three (least squares starts from classical MDS).
MdsResult mds(const Eigen::MatrixXd& D, MdsMethod method, const MdsOptions& options = {});

/// Raw stress sum_{i<j} (D_ij - ||x_i - x_j||)^2 (lower triangle of D). `threads` as in MdsOptions.
double raw_stress(const Eigen::MatrixXd& D, const Eigen::MatrixXd& X, int threads = 0);

namespace detail {

/// Top-k eigenpairs (algebraically largest eigenvalues, descending) of a symmetric n x n operator.
struct EigenPairs {
    Eigen::VectorXd values;   ///< k eigenvalues, descending
    Eigen::MatrixXd vectors;  ///< n x k orthonormal eigenvectors
    int iterations = 0;       ///< operator applications (blocks)
    bool shifted = false;     ///< a restart on B + sigma I was needed
};

/// Block subspace iteration with Rayleigh-Ritz (block size min(n, k + 4)) for the operator
/// `apply(Q) = B Q` (Q n x p). Throws NumericalError if not converged within max_iterations.
EigenPairs top_eigenpairs(Eigen::Index n, int k,
                          const std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>& apply,
                          double tolerance, int max_iterations, std::uint64_t seed,
                          const ProgressFn& progress = {});

}  // namespace detail

}  // namespace canonform::numerics
