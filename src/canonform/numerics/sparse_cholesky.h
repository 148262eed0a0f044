// canonform: the sparse LDL^T factorisation used by the core (factor once, solve many times).
//
// With CHOLMOD (SuiteSparse, Debian's libsuitesparse-dev) found at configure time, this is
// CHOLMOD's simplicial LDL^T, whose solves treat all right-hand-side columns in one sweep over
// the factor: faster than Eigen's SimplicialLDLT for the three coordinates of a SMACOF step (the
// measurement is in the README's "Speed" section). Without it, Eigen's SimplicialLDLT (AMD ordering).
// Both report failure through ok(); the caller turns that into a NumericalError.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>

namespace canonform {

/// LDL^T factorisation of a symmetric positive (semi-)definite sparse matrix.
class SparseCholesky {
public:
    SparseCholesky();
    ~SparseCholesky();
    SparseCholesky(SparseCholesky&&) noexcept;
    SparseCholesky& operator=(SparseCholesky&&) noexcept;

    /// Factors A (lower triangle read). Returns ok().
    bool compute(const Eigen::SparseMatrix<double>& A);
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

}  // namespace canonform
