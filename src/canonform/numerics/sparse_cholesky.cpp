// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/sparse_cholesky.h"

#include "canonform/common/errors.h"

#ifdef CANONFORM_HAVE_CHOLMOD
#include <cholmod.h>
#else
#include <Eigen/SparseCholesky>
#endif

namespace canonform::numerics {

namespace {
void check_shapes(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering) {
    if (A.rows() != A.cols()) throw InputError("sparse Cholesky: the matrix is not square");
    if (!ordering.empty() && static_cast<Eigen::Index>(ordering.size()) != A.rows())
        throw InputError("sparse Cholesky: the given ordering does not have one entry per row");
}
}  // namespace

#ifdef CANONFORM_HAVE_CHOLMOD
// CHOLMOD called directly rather than through Eigen's CholmodSimplicialLDLT, with the settings
// that wrapper uses (simplicial, factor kept as LDL^T, default orderings), so the factor and the
// solutions are the same to the bit; two things the wrapper does not offer: a given ordering
// (cholmod_analyze_p with CHOLMOD_GIVEN, which skips AMD) and solves that keep their workspace
// (cholmod_solve2) instead of allocating the solution and two work arrays on every call.
struct SparseCholesky::Impl {
    cholmod_common c{};
    cholmod_factor* L = nullptr;
    cholmod_dense* X = nullptr;  // solve2 workspaces, kept between solves
    cholmod_dense* Y = nullptr;
    cholmod_dense* E = nullptr;

    Impl() {
        cholmod_start(&c);
        c.final_asis = 1;
        c.supernodal = CHOLMOD_SIMPLICIAL;
        c.print = 0;  // no messages on stderr: failures reach the caller through ok()
    }
    ~Impl() {
        free_workspace();
        if (L) cholmod_free_factor(&L, &c);
        cholmod_finish(&c);
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    void free_workspace() {
        if (X) cholmod_free_dense(&X, &c);
        if (Y) cholmod_free_dense(&Y, &c);
        if (E) cholmod_free_dense(&E, &c);
    }
};

namespace {
/// A CHOLMOD view (no copy) of the lower triangle of a compressed column-major matrix.
cholmod_sparse view_lower(const Eigen::SparseMatrix<double>& A) {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.x = const_cast<double*>(A.valuePtr());
    s.stype = -1;  // symmetric, lower triangle read
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
}
}  // namespace

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering) {
    ok_ = false;
    check_shapes(A, ordering);
    Eigen::SparseMatrix<double> compressed;
    const Eigen::SparseMatrix<double>* M = &A;
    if (!A.isCompressed()) {
        compressed = A;
        compressed.makeCompressed();
        M = &compressed;
    }
    cholmod_common& c = impl_->c;
    impl_->free_workspace();
    if (impl_->L) cholmod_free_factor(&impl_->L, &c);
    cholmod_sparse a = view_lower(*M);
    if (ordering.empty()) {
        c.nmethods = 0;  // CHOLMOD's default: AMD (METIS only if AMD fills badly)
        impl_->L = cholmod_analyze(&a, &c);
    } else {
        c.nmethods = 1;  // only the given ordering (with nmethods 0 AMD would be tried too)
        c.method[0].ordering = CHOLMOD_GIVEN;
        impl_->L = cholmod_analyze_p(&a, const_cast<int*>(ordering.data()), nullptr, 0, &c);
        c.nmethods = 0;
    }
    if (!impl_->L || c.status < CHOLMOD_OK) return false;  // e.g. the given ordering is no permutation
    double beta[2] = {0.0, 0.0};
    cholmod_factorize_p(&a, beta, nullptr, 0, impl_->L, &c);
    ok_ = c.status >= CHOLMOD_OK && impl_->L->minor == impl_->L->n;
    return ok_;
}

std::vector<int> SparseCholesky::ordering() const {
    const cholmod_factor* L = impl_->L;
    if (!L || !L->Perm) return {};
    const int* p = static_cast<const int*>(L->Perm);
    return std::vector<int>(p, p + L->n);
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
    ok_ = false;
    Eigen::MatrixXd X;
    if (!impl_->L || static_cast<size_t>(B.rows()) != impl_->L->n) return X;
    cholmod_dense b{};
    b.nrow = static_cast<size_t>(B.rows());
    b.ncol = static_cast<size_t>(B.cols());
    b.nzmax = b.nrow * b.ncol;
    b.d = b.nrow;
    b.x = const_cast<double*>(B.data());
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, impl_->L, &b, nullptr, &impl_->X, nullptr, &impl_->Y, &impl_->E, &impl_->c))
        return X;
    X = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(impl_->X->x), B.rows(), B.cols());
    ok_ = X.allFinite();
    return X;
}

const char* SparseCholesky::backend() { return "CHOLMOD simplicial LDL^T"; }

#else  // Eigen's SimplicialLDLT

struct SparseCholesky::Impl {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
};

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering) {
    check_shapes(A, ordering);
    impl_->factor.compute(A);  // Eigen's own AMD ordering: a given one is not used here
    ok_ = impl_->factor.info() == Eigen::Success;
    return ok_;
}

std::vector<int> SparseCholesky::ordering() const { return {}; }

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
    Eigen::MatrixXd X = impl_->factor.solve(B);
    ok_ = impl_->factor.info() == Eigen::Success && X.allFinite();
    return X;
}

const char* SparseCholesky::backend() { return "Eigen SimplicialLDLT"; }

#endif

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

}  // namespace canonform::numerics
