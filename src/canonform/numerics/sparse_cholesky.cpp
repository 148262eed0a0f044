#include "canonform/numerics/sparse_cholesky.h"

#ifdef CANONFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#else
#include <Eigen/SparseCholesky>
#endif

namespace canonform {

struct SparseCholesky::Impl {
#ifdef CANONFORM_HAVE_CHOLMOD
    Eigen::CholmodSimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
#else
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
#endif
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& A) {
    impl_->factor.compute(A);
    ok_ = impl_->factor.info() == Eigen::Success;
    return ok_;
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
    Eigen::MatrixXd X = impl_->factor.solve(B);
    ok_ = impl_->factor.info() == Eigen::Success && X.allFinite();
    return X;
}

const char* SparseCholesky::backend() {
#ifdef CANONFORM_HAVE_CHOLMOD
    return "CHOLMOD simplicial LDL^T";
#else
    return "Eigen SimplicialLDLT";
#endif
}

}  // namespace canonform
