// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the sparse LDL^T factorisation used by the core (factor once, solve many times).
//
// With CHOLMOD (SuiteSparse, Debian's libsuitesparse-dev) found at configure time, this is
// CHOLMOD's simplicial LDL^T, whose solves treat all right-hand-side columns in one sweep over
// the factor: faster than Eigen's SimplicialLDLT for the three coordinates of a SMACOF step
// (docs/benchmarks.md, "Figures behind design choices"). Without it, Eigen's SimplicialLDLT (AMD ordering).
// Both report failure through ok(); the caller turns that into a NumericalError.
//
// A factorisation can start from a given fill-reducing ordering, e.g. ordering() of an earlier
// factorisation of a matrix with (nearly) the same sparsity pattern: CHOLMOD then skips its AMD
// step, the larger part of its symbolic analysis (the Euclidean canonical form factors the
// cotangent Laplacian and SMACOF's V, both on the mesh's edges: euclidean_canonical_form.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace canonform::numerics {

/// LDL^T factorisation of a symmetric positive (semi-)definite sparse matrix.
class SparseCholesky {
public:
    SparseCholesky();
    ~SparseCholesky();
    SparseCholesky(SparseCholesky&&) noexcept;
    SparseCholesky& operator=(SparseCholesky&&) noexcept;

    /// Factors A (n x n, lower triangle read). `ordering`: empty = CHOLMOD's own (AMD), else a
    /// permutation of 0..n-1 (entry k = the row of A eliminated k-th; CHOLMOD may post-order
    /// it, which keeps its fill). Ignored by the Eigen fallback. Returns ok(); false also for an
    /// ordering that is no permutation. Throws InputError if A is not square or the ordering
    /// has the wrong length.
    bool compute(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering = {});
    /// The ordering the last compute() used (n entries, as `ordering` above); empty with the
    /// Eigen fallback or before compute().
    std::vector<int> ordering() const;
    /// True if the last compute() or solve() succeeded.
    bool ok() const { return ok_; }
    /// Solves A X = B for all columns of B.
    Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
    /// Name of the back-end ("CHOLMOD simplicial LDL^T" or "Eigen SimplicialLDLT").
    static const char* backend();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    mutable bool ok_ = false;
};

}  // namespace canonform::numerics
