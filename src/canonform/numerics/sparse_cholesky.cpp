// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/sparse_cholesky.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/errors.h"
#include "canonform/common/vector4d.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace canonform::numerics {

namespace {

void check_shapes(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering) {
    if (A.rows() != A.cols()) throw InputError("sparse Cholesky: the matrix is not square");
    if (!ordering.empty() && static_cast<Eigen::Index>(ordering.size()) != A.rows())
        throw InputError("sparse Cholesky: the given ordering does not have one entry per row");
}

using Permutation = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;

}  // namespace

struct SparseCholesky::Impl {
    // P A P^T = L D L^T: P moves row order[k] of A to row k; the factor of the permuted matrix by
    // Eigen's up-looking LDL^T without a further ordering.
    std::vector<int> order;
    Permutation P;
    Eigen::SparseMatrix<double> permuted;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt;
    std::vector<double> inverse_d;  // 1 / D
    std::vector<double> z;          // the right-hand sides in elimination order, interleaved
    // L's row indices as 16 bits when n <= 65536 (what the direct solver meets: below
    // kMultigridFrom rows): a sixth less to read per solve, the same arithmetic.
    std::vector<std::uint16_t> short_rows;
};

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& A, const std::vector<int>& ordering) {
    ok_ = false;
    check_shapes(A, ordering);
    Impl& f = *impl_;
    const int n = static_cast<int>(A.rows());
    f.order.clear();
    if (ordering.empty()) {
        // Approximate minimum degree on the symmetric pattern (Eigen's AMDOrdering of the
        // self-adjoint view: the full pattern from the lower triangle, with the diagonal, built
        // once; given a plain matrix it would form A^T + A of it again).
        Permutation inverse;
        Eigen::AMDOrdering<int>()(A.selfadjointView<Eigen::Lower>(), inverse);
        f.order.assign(inverse.indices().data(), inverse.indices().data() + n);
    } else {
        std::vector<char> seen(static_cast<size_t>(n), 0);
        for (const int k : ordering) {
            if (k < 0 || k >= n || seen[static_cast<size_t>(k)]) return false;  // not a permutation
            seen[static_cast<size_t>(k)] = 1;
        }
        f.order = ordering;
    }
    f.P.resize(n);
    for (int k = 0; k < n; ++k) f.P.indices()[f.order[static_cast<size_t>(k)]] = k;
    f.permuted.resize(n, n);
    f.permuted.selfadjointView<Eigen::Lower>() = A.selfadjointView<Eigen::Lower>().twistedBy(f.P);
    f.ldlt.compute(f.permuted);
    if (f.ldlt.info() != Eigen::Success) return false;
    const Eigen::VectorXd D = f.ldlt.vectorD();
    f.inverse_d.resize(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) f.inverse_d[static_cast<size_t>(k)] = 1.0 / D(k);
    const auto& L = f.ldlt.matrixL().nestedExpression();
    f.short_rows.clear();
    if (n <= 65536) f.short_rows.assign(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros());
    ok_ = D.allFinite();
    return ok_;
}

std::vector<int> SparseCholesky::ordering() const {
    return impl_->order;
}

namespace {

// Solves L D L^T z = z in place for m interleaved columns (z[i * m + c]): a forward sweep over L's
// columns, the diagonal, a backward sweep - each column of L read once for all m right-hand sides.
template <int M>
void ldl_solve(const int* Lp, const int* Li, const double* Lx, const double* inverse_d, int n, int m_runtime,
               double* z) {
    const int m = M > 0 ? M : m_runtime;
    for (int j = 0; j < n; ++j) {
        const double* zj = z + static_cast<std::ptrdiff_t>(j) * m;
        if constexpr (M > 0) {
            // Row j's values in registers: the compiler cannot know that zi (a row below j) is not
            // zj, so without the copy it reloads zj[c] after every store.
            double a[M];
            for (int c = 0; c < M; ++c) a[c] = zj[c];
            for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
                double* zi = z + static_cast<std::ptrdiff_t>(Li[p]) * M;
                const double l = Lx[p];
                for (int c = 0; c < M; ++c) zi[c] -= l * a[c];
            }
            continue;
        }
        for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
            double* zi = z + static_cast<std::ptrdiff_t>(Li[p]) * m;
            const double l = Lx[p];
            for (int c = 0; c < m; ++c) zi[c] -= l * zj[c];
        }
    }
    for (int j = 0; j < n; ++j)
        for (int c = 0; c < m; ++c) z[static_cast<std::ptrdiff_t>(j) * m + c] *= inverse_d[j];
    for (int j = n - 1; j >= 0; --j) {
        double* zj = z + static_cast<std::ptrdiff_t>(j) * m;
        if constexpr (M > 0) {
            // Row j accumulated in registers, in the same order as below.
            double a[M];
            for (int c = 0; c < M; ++c) a[c] = zj[c];
            for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
                const double* zi = z + static_cast<std::ptrdiff_t>(Li[p]) * M;
                const double l = Lx[p];
                for (int c = 0; c < M; ++c) a[c] -= l * zi[c];
            }
            for (int c = 0; c < M; ++c) zj[c] = a[c];
            continue;
        }
        for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
            const double* zi = z + static_cast<std::ptrdiff_t>(Li[p]) * m;
            const double l = Lx[p];
            for (int c = 0; c < m; ++c) zj[c] -= l * zi[c];
        }
    }
}

// ldl_solve() of three columns with each row's three values in a vector of four (the fourth 0 and
// unused): the same multiplications and subtractions per value in the same order (one AVX2
// instruction in the AVX2 clone, two SSE2 ones elsewhere; no FMA in either), so the same bits as
// three scalars, with a third of the instructions.
template <class Index>
CANONFORM_CLONES void ldl_solve3_in4(const int* Lp, const Index* Li, const double* Lx,
                                     const double* inverse_d, int n, double* z) {
    for (int j = 0; j < n; ++j) {
        const v4d a = load4d(z + static_cast<std::ptrdiff_t>(j) * 4);
        for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
            double* zi = z + static_cast<std::ptrdiff_t>(Li[p]) * 4;
            store4d(zi, load4d(zi) - Lx[p] * a);
        }
    }
    for (int j = 0; j < n; ++j) {
        double* zj = z + static_cast<std::ptrdiff_t>(j) * 4;
        store4d(zj, load4d(zj) * inverse_d[j]);
    }
    for (int j = n - 1; j >= 0; --j) {
        double* zj = z + static_cast<std::ptrdiff_t>(j) * 4;
        v4d a = load4d(zj);
        for (int p = Lp[j]; p < Lp[j + 1]; ++p)
            a -= Lx[p] * load4d(z + static_cast<std::ptrdiff_t>(Li[p]) * 4);
        store4d(zj, a);
    }
}

}  // namespace

Eigen::MatrixXd SparseCholesky::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const {
    ok_ = false;
    Eigen::MatrixXd X;
    Impl& f = *impl_;
    const Eigen::Index n = static_cast<Eigen::Index>(f.order.size());
    if (n == 0 || f.inverse_d.empty() || B.rows() != n) return X;
    const auto& L = f.ldlt.matrixL().nestedExpression();
    const int m = static_cast<int>(B.cols());
    X.resize(n, m);
    const int* Lp = L.outerIndexPtr();
    const int* Li = L.innerIndexPtr();
    const double* Lx = L.valuePtr();
    const int nn = static_cast<int>(n);
    // The right-hand sides in elimination order, a row's m values side by side; three take a row of
    // four (the fourth 0), as ldl_solve3_in4() reads them.
    const int stride = m == 3 ? 4 : m;
    f.z.resize(static_cast<size_t>(n) * static_cast<size_t>(stride));
    const int* order = f.order.data();
    double* z = f.z.data();
    const Eigen::Index ldb = B.outerStride();
    const double* b = B.data();
    double* x = X.data();
    if (m == 3) {
        const double *b0 = b, *b1 = b + ldb, *b2 = b + 2 * ldb;
        for (Eigen::Index k = 0; k < n; ++k) {
            const Eigen::Index r = order[k];
            double* zk = z + 4 * k;
            zk[0] = b0[r];
            zk[1] = b1[r];
            zk[2] = b2[r];
            zk[3] = 0.0;
        }
        if (!f.short_rows.empty())
            ldl_solve3_in4(Lp, f.short_rows.data(), Lx, f.inverse_d.data(), nn, z);
        else
            ldl_solve3_in4(Lp, Li, Lx, f.inverse_d.data(), nn, z);
        double *x0 = x, *x1 = x + n, *x2 = x + 2 * n;
        for (Eigen::Index k = 0; k < n; ++k) {
            const Eigen::Index r = order[k];
            const double* zk = z + 4 * k;
            x0[r] = zk[0];
            x1[r] = zk[1];
            x2[r] = zk[2];
        }
    } else {
        for (Eigen::Index k = 0; k < n; ++k)
            for (int c = 0; c < m; ++c) z[k * m + c] = b[c * ldb + order[k]];
        if (m == 1)
            ldl_solve<1>(Lp, Li, Lx, f.inverse_d.data(), nn, m, z);
        else
            ldl_solve<0>(Lp, Li, Lx, f.inverse_d.data(), nn, m, z);
        for (Eigen::Index k = 0; k < n; ++k)
            for (int c = 0; c < m; ++c) x[c * n + order[k]] = z[k * m + c];
    }
    ok_ = X.allFinite();
    return X;
}

const char* SparseCholesky::backend() {
    return "simplicial LDL^T (AMD ordering)";
}

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

}  // namespace canonform::numerics
