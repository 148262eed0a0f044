// SPDX-License-Identifier: GPL-3.0-or-later
// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's tridiagonalisation (Eigen/Core's
// matrix-vector kernels) when Eigen is not a system include, as in standalone g++ -I builds.
#if !defined(__clang__)  // (no such warning in clang)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "canonform/numerics/mds.h"

#include "canonform/common/parallel.h"
#include "canonform/numerics/portable_math.h"

#include "canonform/numerics/smacof.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <thread>

namespace canonform::numerics {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Worker count: `requested` (0 = every hardware thread), at most one per 128 points (threads do
/// not pay for themselves below that), at least 1.
int resolve_threads(int requested, Index n) {
    ParallelOptions o;
    o.threads = requested;
    o.grain = 128;
    return parallel_workers(n, o);
}

/// Runs f(0), ..., f(T-1) concurrently (f(0) on the calling thread); rethrows the first error.
template <class F>
void run_parallel(int T, const F& f) {
    ParallelOptions o;
    o.threads = T;
    parallel_for(
        T, [&](std::ptrdiff_t t, int) { f(static_cast<int>(t)); }, o);
}

/// T + 1 row boundaries splitting rows [0, n) into T ranges of equal size.
std::vector<Index> equal_bounds(Index n, int T) {
    std::vector<Index> b(static_cast<size_t>(T) + 1);
    for (int t = 0; t <= T; ++t) b[static_cast<size_t>(t)] = n * t / T;
    return b;
}

/// T + 1 row boundaries splitting the strict lower triangle (row i holds n - 1 - i pairs) into T
/// ranges with about the same number of pairs.
std::vector<Index> triangle_bounds(Index n, int T) {
    std::vector<Index> b(static_cast<size_t>(T) + 1, n);
    b[0] = 0;
    const double total = 0.5 * static_cast<double>(n) * static_cast<double>(n - 1);
    double acc = 0;
    int t = 1;
    for (Index i = 0; i < n && t < T; ++i) {
        acc += static_cast<double>(n - 1 - i);
        while (t < T && acc >= total * t / T) b[static_cast<size_t>(t++)] = i + 1;
    }
    return b;
}

std::string entry(Index i, Index j) {
    std::ostringstream s;
    s << "D(" << i << ", " << j << ")";
    return s.str();
}

/// Shape checks always; the O(N^2) value checks if options.check_input.
void validate(const MatrixXd& D, const MdsOptions& options, const char* who) {
    std::ostringstream msg;
    msg << who << ": ";
    if (options.dim < 1) {
        msg << "the embedding dimension must be at least 1 (got " << options.dim << ")";
        throw InputError(msg.str());
    }
    if (D.rows() != D.cols() || D.rows() == 0) {
        msg << "the distance matrix is " << D.rows() << " x " << D.cols()
            << "; it must be square and non-empty";
        throw InputError(msg.str());
    }
    const Index n = D.rows();
    if (n < options.dim + 1) {
        msg << "a " << options.dim << "-dimensional embedding needs at least " << options.dim + 1
            << " points; the distance matrix has " << n;
        throw InputError(msg.str());
    }
    if (!options.check_input) return;
    if (!D.allFinite() || D.minCoeff() < 0) {
        for (Index j = 0; j < n; ++j)
            for (Index i = 0; i < n; ++i) {
                const double v = D(i, j);
                if (!std::isfinite(v)) {
                    msg << entry(i, j) << " = " << v << " is not finite";
                    throw InputError(msg.str());
                }
                if (v < 0) {
                    msg << entry(i, j) << " = " << v << " is negative; distances must be non-negative";
                    throw InputError(msg.str());
                }
            }
    }
    const double tol = options.symmetry_tolerance * D.maxCoeff();
    for (Index i = 0; i < n; ++i)
        if (std::abs(D(i, i)) > tol) {
            msg << entry(i, i) << " = " << D(i, i) << "; the diagonal must be zero";
            throw InputError(msg.str());
        }
    constexpr Index kBlock = 64;
    for (Index jb = 0; jb < n; jb += kBlock)
        for (Index ib = jb; ib < n; ib += kBlock) {
            const Index je = std::min(n, jb + kBlock), ie = std::min(n, ib + kBlock);
            for (Index j = jb; j < je; ++j)
                for (Index i = std::max(ib, j + 1); i < ie; ++i)
                    if (std::abs(D(i, j) - D(j, i)) > tol) {
                        msg << "the distance matrix is not symmetric: " << entry(i, j) << " = " << D(i, j)
                            << " but " << entry(j, i) << " = " << D(j, i)
                            << " (symmetrise it first, e.g. (D + D^T) / 2)";
                        throw InputError(msg.str());
                    }
        }
}

void centre(MatrixXd& X) {
    X.rowwise() -= X.colwise().mean();
}

/// Per-thread scratch of the all-pairs stress pass.
struct PassScratch {
    MatrixXd acc;            // n x dim accumulator of B(X) X (blocks > 0 only)
    Eigen::ArrayXd dist, f;  // length n
    double stress = 0;
};

/// Rows [r0, r1) of the strict lower triangle: pairs (i, j), j > i, target D(j, i) (column i of D,
/// contiguous). Adds their stress to s.stress; if acc, adds (D_ij / d_ij)(x_i - x_j) to row i and
/// subtracts it from row j (the pair's part of B(X) X; b_ij = 0 where d_ij = 0).
void pair_pass(const MatrixXd& D, const MatrixXd& X, Index r0, Index r1, MatrixXd* acc, PassScratch& s) {
    const Index n = X.rows(), dim = X.cols();
    double stress = 0;
    for (Index i = r0; i < r1; ++i) {
        const Index m = n - 1 - i;
        if (m <= 0) continue;
        auto d = s.dist.head(m);
        if (dim == 3) {  // the common case, fused into one pass
            d = ((X(i, 0) - X.col(0).segment(i + 1, m).array()).square() +
                 (X(i, 1) - X.col(1).segment(i + 1, m).array()).square() +
                 (X(i, 2) - X.col(2).segment(i + 1, m).array()).square())
                    .sqrt();
        } else {
            d.setZero();
            for (Index c = 0; c < dim; ++c) d += (X(i, c) - X.col(c).segment(i + 1, m).array()).square();
            d = d.sqrt();
        }
        const auto delta = D.col(i).segment(i + 1, m).array();
        stress += (delta - d).square().sum();
        if (!acc) continue;
        auto g = s.f.head(m);
        g = delta / d;
        if (d.minCoeff() <= 0)
            for (Index k = 0; k < m; ++k)
                if (!(d[k] > 0)) g[k] = 0;
        // Row i: sum_j g_j (x_i - x_j) = x_i sum(g) - X_j^T g (one matrix-vector pass).
        acc->row(i).noalias() += g.sum() * X.row(i) - g.matrix().transpose() * X.middleRows(i + 1, m);
        for (Index c = 0; c < dim; ++c)
            acc->col(c).segment(i + 1, m).array() += g * (X.col(c).segment(i + 1, m).array() - X(i, c));
    }
    s.stress += stress;
}

/// S(X) and B(X) X for all pairs. The strict lower triangle is split into a fixed number of row
/// blocks with about equal numbers of pairs, each with its own accumulator, summed in block order:
/// the threads only decide which worker does a block, so the result is the same bits for every
/// thread count (with one accumulator per thread it depended on the number of cores).
class AllPairsPass {
public:
    static constexpr int kBlocks = 16;

    AllPairsPass(const MatrixXd& D, Index dim, int threads)
        : D_(D),
          B_(static_cast<int>(std::min<Index>(kBlocks, std::max<Index>(D.rows(), 1)))),
          T_(std::min(resolve_threads(threads, D.rows()), B_)),
          bounds_(triangle_bounds(D.rows(), B_)),
          scratch_(static_cast<size_t>(B_)) {
        const Index n = D.rows();
        for (int b = 0; b < B_; ++b) {
            PassScratch& s = scratch_[static_cast<size_t>(b)];
            s.dist.resize(n);
            s.f.resize(n);
            if (b > 0) s.acc.resize(n, dim);
        }
    }

    /// S(X) in *stress; B(X) X in *BX if BX is given.
    void run(const MatrixXd& X, MatrixXd* BX, double* stress) {
        if (BX) BX->setZero(X.rows(), X.cols());
        run_parallel(T_, [&](int t) {
            for (int b = t; b < B_; b += T_) {
                PassScratch& s = scratch_[static_cast<size_t>(b)];
                s.stress = 0;
                MatrixXd* acc = nullptr;
                if (BX) {
                    if (b > 0) {
                        s.acc.setZero(X.rows(), X.cols());
                        acc = &s.acc;
                    } else {
                        acc = BX;  // block 0 comes first in the sum
                    }
                }
                pair_pass(D_, X, bounds_[static_cast<size_t>(b)], bounds_[static_cast<size_t>(b) + 1], acc,
                          s);
            }
        });
        double total = 0;
        for (int b = 0; b < B_; ++b) {
            total += scratch_[static_cast<size_t>(b)].stress;
            if (BX && b > 0) *BX += scratch_[static_cast<size_t>(b)].acc;
        }
        *stress = total;
    }

private:
    const MatrixXd& D_;
    int B_, T_;
    std::vector<Index> bounds_;
    std::vector<PassScratch> scratch_;
};

/// A^T B (or A B) with the inner dimension summed in blocks of 64, in order. Eigen's matrix product
/// splits a long inner dimension into blocks sized from the L1 cache that CPUID reports (Eigen's
/// smallest such block, for an 8 KiB L1, holds 96 doubles), so its rounding depended on the CPU;
/// a product of 64 leaves it nothing to split.
constexpr Index kInnerBlock = 64;
MatrixXd transpose_times(const MatrixXd& A, const MatrixXd& B) {
    MatrixXd out = MatrixXd::Zero(A.cols(), B.cols());
    for (Index k = 0; k < A.rows(); k += kInnerBlock) {
        const Index len = std::min(kInnerBlock, A.rows() - k);
        out.noalias() += A.middleRows(k, len).transpose() * B.middleRows(k, len);
    }
    return out;
}
MatrixXd times(const MatrixXd& A, const MatrixXd& B) {
    MatrixXd out = MatrixXd::Zero(A.rows(), B.cols());
    for (Index k = 0; k < A.cols(); k += kInnerBlock) {
        const Index len = std::min(kInnerBlock, A.cols() - k);
        out.noalias() += A.middleCols(k, len) * B.middleRows(k, len);
    }
    return out;
}

/// Orthonormal basis (n x p) of the columns of Z (Householder QR; rank deficiency is completed by
/// arbitrary orthonormal directions).
MatrixXd orthonormalise(const MatrixXd& Z) {
    Eigen::HouseholderQR<MatrixXd> qr(Z);
    return qr.householderQ() * MatrixXd::Identity(Z.rows(), Z.cols());
}

/// Flips each column so that its entry of largest magnitude is positive (reproducible signs).
void fix_signs(MatrixXd& V) {
    for (Index c = 0; c < V.cols(); ++c) {
        Index k = 0;
        V.col(c).cwiseAbs().maxCoeff(&k);
        if (V(k, c) < 0) V.col(c) *= -1;
    }
}

/// X = V diag(sqrt(max(lambda, 0))), centred.
MatrixXd scaled_coordinates(const detail::EigenPairs& e) {
    MatrixXd X = e.vectors * e.values.cwiseMax(0.0).cwiseSqrt().asDiagonal();
    centre(X);
    return X;
}

}  // namespace

namespace detail {

EigenPairs top_eigenpairs(Index n, int k, const std::function<MatrixXd(const MatrixXd&)>& apply,
                          double tolerance, int max_iterations, std::uint64_t seed,
                          const ProgressFn& progress) {
    if (n < 1 || k < 1 || k > n) throw InputError("top_eigenpairs: need 1 <= k <= n");
    const Index p = std::min<Index>(n, k + 4);
    std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
    StandardNormalDraws normal;  // not std::normal_distribution: its std::log differs between C libraries
    MatrixXd Q(n, p);
    for (Index c = 0; c < p; ++c)
        for (Index i = 0; i < n; ++i) Q(i, c) = normal(rng);
    Q = orthonormalise(Q);
    double sigma = 0;  // the operator iterated is B + sigma I
    bool shifted = false;
    for (int it = 1; it <= max_iterations; ++it) {
        MatrixXd Z = apply(Q);
        if (Z.rows() != n || Z.cols() != p)
            throw NumericalError("top_eigenpairs: the operator returned the wrong shape");
        if (sigma != 0) Z += sigma * Q;
        if (!Z.allFinite()) throw NumericalError("eigensolver: the operator produced non-finite values");
        // Rayleigh-Ritz on span(Q): H = Q^T (B + sigma) Q, Ritz vectors U = Q W, (B + sigma) U = Z W.
        MatrixXd H = transpose_times(Q, Z);
        H = 0.5 * (H + H.transpose()).eval();
        Eigen::SelfAdjointEigenSolver<MatrixXd> es(H);
        if (es.info() != Eigen::Success) throw NumericalError("eigensolver: the Rayleigh-Ritz step failed");
        const VectorXd theta = es.eigenvalues().reverse();  // descending
        const MatrixXd W = es.eigenvectors().rowwise().reverse();
        const MatrixXd U = Q * W, BU = Z * W;
        const VectorXd lambda = theta.array() - sigma;  // Ritz values of B
        const double scale = lambda.cwiseAbs().maxCoeff();
        bool converged = true;
        for (int j = 0; j < k && scale > 0; ++j) {
            const double res = (BU.col(j) - theta(j) * U.col(j)).norm();
            if (!(res <= tolerance * std::max(std::abs(lambda(j)), 1e-6 * scale))) converged = false;
        }
        if (converged) {
            // Subspace iteration finds the largest |lambda|. If every unwanted Ritz value is a
            // negative one larger in magnitude than the k-th wanted, a positive eigenvalue may lie
            // outside the block: restart on B + sigma I (sigma = |most negative Ritz value|),
            // whose largest eigenvalues are B's algebraically largest.
            if (!shifted && p < n) {
                const double t = std::max(lambda(k - 1), 0.0) + 1e-6 * scale;
                bool suspicious = true;
                for (Index j = k; j < p; ++j)
                    if (!(-lambda(j) > t)) suspicious = false;
                if (suspicious) {
                    sigma = -lambda(p - 1);
                    shifted = true;
                    // A fresh random start: U has (numerically) no component along the missed
                    // eigenvectors, so it would "converge" at once to the wrong ones.
                    for (Index c = 0; c < p; ++c)
                        for (Index i = 0; i < n; ++i) Q(i, c) = normal(rng);
                    Q = orthonormalise(Q);
                    continue;
                }
            }
            EigenPairs out;
            out.values = lambda.head(k);
            out.vectors = U.leftCols(k);
            fix_signs(out.vectors);
            out.iterations = it;
            out.shifted = shifted;
            return out;
        }
        Q = orthonormalise(Z);
        if (it % 10 == 0)
            report_progress(progress, static_cast<double>(it) / max_iterations, "MDS eigenvectors");
    }
    std::ostringstream msg;
    msg << "classical MDS: the top " << k << " eigenvectors did not converge in " << max_iterations
        << " subspace iterations (relative residual tolerance " << tolerance
        << "); raise eigen_max_iterations or eigen_tolerance";
    throw NumericalError(msg.str());
}

}  // namespace detail

double raw_stress(const MatrixXd& D, const MatrixXd& X, int threads) {
    if (D.rows() != D.cols() || X.rows() != D.rows() || X.cols() < 1)
        throw InputError("raw stress: D must be N x N and X N x dim (dim >= 1)");
    AllPairsPass pass(D, X.cols(), threads);
    double s = 0;
    pass.run(X, nullptr, &s);
    return s;
}

MdsResult classical_mds(const MatrixXd& D, const MdsOptions& options) {
    validate(D, options, "classical MDS");
    const Index n = D.rows();
    const int T = resolve_threads(options.threads, n);
    // Rows in blocks of 16 at fixed places (multiples of 16), whatever the thread count: Eigen's
    // product takes another kernel for a shorter block, so the rows' rounding followed the blocks.
    constexpr Index kRows = 16;
    const std::vector<Index> bounds = equal_bounds((n + kRows - 1) / kRows, T);  // in blocks
    std::vector<MatrixXd> squares(static_cast<size_t>(T), MatrixXd(n, kRows));
    // B Q = -1/2 J D^(2) J Q; row i of D^(2) Y is column i of D squared, times Y (D symmetric).
    const auto apply = [&](const MatrixXd& Q) {
        const MatrixXd Y = Q.rowwise() - Q.colwise().mean();
        MatrixXd Z(n, Q.cols());
        run_parallel(T, [&](int t) {
            MatrixXd& S = squares[static_cast<size_t>(t)];
            const Index r1 = std::min(n, bounds[static_cast<size_t>(t) + 1] * kRows);
            for (Index i0 = bounds[static_cast<size_t>(t)] * kRows; i0 < r1; i0 += kRows) {
                const Index nb = std::min(kRows, r1 - i0);
                S.leftCols(nb) = D.middleCols(i0, nb).array().square().matrix();
                Z.middleRows(i0, nb) = transpose_times(S.leftCols(nb), Y);
            }
        });
        centre(Z);
        Z *= -0.5;
        return Z;
    };
    const detail::EigenPairs e =
        detail::top_eigenpairs(n, options.dim, apply, options.eigen_tolerance, options.eigen_max_iterations,
                               options.seed, options.progress);
    MdsResult r;
    r.X = scaled_coordinates(e);
    r.iterations = e.iterations;
    r.converged = true;
    r.eigenvalues = e.values;
    r.initial_stress = r.final_stress = options.compute_stress ? raw_stress(D, r.X, options.threads) : kNaN;
    return r;
}

MdsResult landmark_mds(const MatrixXd& D, const MdsOptions& options) {
    validate(D, options, "landmark MDS");
    const Index n = D.rows();
    const int dim = options.dim;
    Index L = options.landmarks;
    if (L == 0) {
        L = 3 * static_cast<Index>(std::ceil(std::sqrt(static_cast<double>(n))));
        L = std::min(std::max<Index>(L, dim + 1), n);
    } else if (L < dim + 1 || L > n) {
        std::ostringstream msg;
        msg << "landmark MDS: " << L << " landmarks requested; a " << dim << "-dimensional embedding of " << n
            << " points needs between " << dim + 1 << " and " << n;
        throw InputError(msg.str());
    }

    // Farthest-point (max-min) sampling from a seeded random first landmark; ties: lowest index.
    MdsResult r;
    std::mt19937_64 rng(options.seed);
    Index next = std::uniform_int_distribution<Index>(0, n - 1)(rng);
    VectorXd nearest = VectorXd::Constant(n, std::numeric_limits<double>::infinity());
    std::vector<char> chosen(static_cast<size_t>(n), 0);
    r.landmarks.reserve(static_cast<size_t>(L));
    for (Index l = 0; l < L; ++l) {
        r.landmarks.push_back(static_cast<int>(next));
        chosen[static_cast<size_t>(next)] = 1;
        nearest = nearest.cwiseMin(D.col(next));
        double best = -1;
        for (Index i = 0; i < n; ++i)
            if (!chosen[static_cast<size_t>(i)] && nearest[i] > best) {
                best = nearest[i];
                next = i;
            }
    }
    report_progress(options.progress, 0.3, "landmark MDS: landmarks chosen");

    // Classical MDS on the landmark block.
    MatrixXd DL2(L, L);
    for (Index b = 0; b < L; ++b)
        for (Index a = 0; a < L; ++a)
            DL2(a, b) = D(r.landmarks[static_cast<size_t>(a)], r.landmarks[static_cast<size_t>(b)]);
    DL2 = DL2.array().square().matrix();
    DL2 = 0.5 * (DL2 + DL2.transpose()).eval();
    const VectorXd mean_sq = DL2.rowwise().mean();  // delta_mu
    MatrixXd BL = DL2;
    BL.rowwise() -= BL.colwise().mean();  // J DL2
    BL.colwise() -= BL.rowwise().mean();  // J DL2 J
    BL = -0.25 * (BL + BL.transpose()).eval();
    detail::EigenPairs e;
    if (L <= 1000) {
        Eigen::SelfAdjointEigenSolver<MatrixXd> es(BL);
        if (es.info() != Eigen::Success)
            throw NumericalError("landmark MDS: the eigensolver of the landmark block failed");
        e.values = es.eigenvalues().reverse().head(dim);
        e.vectors = es.eigenvectors().rowwise().reverse().leftCols(dim);
        fix_signs(e.vectors);
    } else {
        e = detail::top_eigenpairs(L, dim, [&BL](const MatrixXd& Q) { return times(BL, Q); },
                                   options.eigen_tolerance, options.eigen_max_iterations, options.seed, {});
    }
    report_progress(options.progress, 0.6, "landmark MDS: landmark block embedded");

    // Triangulation: x_a = -1/2 L^# (delta_a - delta_mu), L^# rows v_k^T / sqrt(lambda_k).
    MatrixXd Pinv_t = MatrixXd::Zero(L, dim);  // (L^#)^T
    const double floor = 1e-10 * std::max(e.values(0), 0.0);
    for (int k = 0; k < dim; ++k)
        if (e.values(k) > floor && e.values(k) > 0) Pinv_t.col(k) = e.vectors.col(k) / std::sqrt(e.values(k));
    MatrixXd S(n, L);
    for (Index l = 0; l < L; ++l)
        S.col(l) = D.col(r.landmarks[static_cast<size_t>(l)]).array().square() - mean_sq(l);
    r.X = -0.5 * times(S, Pinv_t);
    centre(r.X);
    r.converged = true;
    r.eigenvalues = e.values;
    r.initial_stress = r.final_stress = options.compute_stress ? raw_stress(D, r.X, options.threads) : kNaN;
    return r;
}

MdsResult least_squares_mds(const MatrixXd& D, const MdsOptions& options, const MatrixXd* X0) {
    validate(D, options, "least-squares MDS");
    const Index n = D.rows(), dim = options.dim;
    MatrixXd X;
    if (X0) {
        if (X0->rows() != n || X0->cols() != dim) {
            std::ostringstream msg;
            msg << "least-squares MDS: the start is " << X0->rows() << " x " << X0->cols() << "; expected "
                << n << " x " << dim;
            throw InputError(msg.str());
        }
        if (!X0->allFinite()) throw InputError("least-squares MDS: the start has non-finite coordinates");
        X = *X0;
    } else {
        MdsOptions c = options;
        c.check_input = false;
        c.compute_stress = false;
        if (options.progress)
            c.progress = [&options](double f, const char* stage) { return options.progress(0.1 * f, stage); };
        X = classical_mds(D, c).X;
        // A zero column (B has < dim positive eigenvalues) would stay zero under every Guttman step.
        const VectorXd norms = X.colwise().norm();
        double amplitude = norms.maxCoeff() / std::sqrt(static_cast<double>(n));
        if (amplitude == 0) amplitude = D.norm() / static_cast<double>(n);
        amplitude *= 1e-4;
        std::mt19937_64 rng(options.seed ^ 0x5bd1e995ULL);
        std::uniform_real_distribution<double> u(-1, 1);
        for (Index col = 0; col < dim; ++col)
            if (norms(col) <= 1e-8 * norms.maxCoeff())
                for (Index i = 0; i < n; ++i) X(i, col) = amplitude * u(rng);
    }
    centre(X);

    AllPairsPass pass(D, dim, options.threads);
    const double inv_n = 1.0 / static_cast<double>(n);
    // V^+ B(X) X = B(X) X / N (1^T B = 0, so no re-centring is needed, but it removes rounding drift).
    const auto step = [&](const MatrixXd& Xk, double* s) {
        MatrixXd BX;
        pass.run(Xk, &BX, s);
        MatrixXd Y = BX * inv_n;
        centre(Y);
        return Y;
    };
    SmacofOptions iteration = options.smacof;
    iteration.progress = options.progress;  // the whole run reports through MdsOptions::progress
    MdsResult r;
    static_cast<SmacofResult&>(r) = run_guttman(step, X, iteration, "least-squares MDS", 0.1);
    return r;
}

ParameterSet<MdsOptions> mds_parameters(const MdsOptions& defaults) {
    ParameterSet<MdsOptions> s(defaults);
    s.include(smacof_parameters(), &MdsOptions::smacof);
    return s;
}

MdsResult mds(const MatrixXd& D, MdsMethod method, const MdsOptions& options) {
    switch (method) {
        case MdsMethod::LeastSquares:
            return least_squares_mds(D, options);
        case MdsMethod::Classical:
            return classical_mds(D, options);
        case MdsMethod::Landmark:
            return landmark_mds(D, options);
    }
    throw InputError("mds: unknown method");
}

}  // namespace canonform::numerics
