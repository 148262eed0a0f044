// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the sparse LDL^T factorisation used by the core (factor once, solve many times).
//
// References: T. A. Davis, "Algorithm 849: A concise sparse Cholesky factorization package", ACM
// TOMS 31(4), 2005 (the up-looking LDL^T with the elimination tree, as Eigen's SimplicialLDLT
// implements it); P. R. Amestoy, T. A. Davis, I. S. Duff, "An approximate minimum degree ordering
// algorithm", SIAM J. Matrix Anal. Appl. 17(4), 1996 (Eigen's AMDOrdering).
//
// P A P^T = L D L^T with a fill-reducing ordering P: AMD on the pattern of A, or a given one. The
// factorisation is Eigen's SimplicialLDLT of the permuted matrix (through its public API, with no
// ordering of its own). The solve is ours: the right-hand-side columns interleaved (row i's m
// values side by side), so one sweep over L serves all of them - SMACOF solves for three
// coordinates at once, and Eigen's solve sweeps L once per column. Each column's arithmetic is the
// same as a one-column solve's, so a column's result does not depend on how many are solved with
// it. Up to 65536 rows (every matrix the direct solver meets by default) the three-column solve
// reads L's row indices as 16 bits: a sixth less to read in a solve that reads all of L twice.
// Failure (a zero pivot, a non-finite value) is reported through ok(); the caller turns it into a
// NumericalError.
//
// A factorisation can start from a given ordering, e.g. ordering() of an earlier factorisation of a
// matrix with (nearly) the same sparsity pattern: the AMD step is then skipped (the Euclidean
// canonical form factors the cotangent Laplacian and SMACOF's V, both on the mesh's edges:
// euclidean_canonical_form.cpp).
//
// Why not CHOLMOD (used here before, in its simplicial mode): Debian's libcholmod links BLAS and
// LAPACK, whose OpenBLAS starts a worker thread per core when loaded that spins for about 0.1 s;
// with the interleaved solve and a reused ordering this factorisation is as fast at 10k and 50k
// vertices (docs/benchmarks.md, "Sparse LDL^T without CHOLMOD"); the core needs Eigen alone.
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

    /// Factors A (n x n, lower triangle read). `ordering`: empty = AMD, else a permutation of
    /// 0..n-1 (entry k = the row of A eliminated k-th), used as given. Returns ok(); false also
    /// for an ordering that is no permutation. Throws InputError if A is not square or the
    /// ordering has the wrong length.
    bool compute(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering = {});
    /// The ordering the last compute() used (n entries, as `ordering` above); empty before
    /// compute().
    std::vector<int> ordering() const;
    /// True if the last compute() or solve() succeeded.
    bool ok() const { return ok_; }
    /// Solves A X = B for all columns of B (a matrix or a block of one: no copy is made of it).
    Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const;
    /// Name of the method ("simplicial LDL^T (AMD ordering)").
    static const char* backend();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    mutable bool ok_ = false;
};

}  // namespace canonform::numerics
