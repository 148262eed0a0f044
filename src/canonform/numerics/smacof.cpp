// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/smacof.h"

#include "canonform/numerics/graph.h"
#include "canonform/numerics/sparse_columns.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/parallel.h"
#include "canonform/common/vector4d.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace canonform::numerics {

const char* to_string(SmacofAcceleration a) {
    switch (a) {
        case SmacofAcceleration::None:
            return "none";
        case SmacofAcceleration::Relaxed:
            return "relaxed";
        case SmacofAcceleration::Rre:
            return "rre";
        case SmacofAcceleration::Mpe:
            return "mpe";
        case SmacofAcceleration::Anderson:
            return "anderson";
    }
    return "?";
}

std::vector<std::string> smacof_acceleration_names() {
    return {"none", "relaxed", "rre", "mpe", "anderson"};
}

SmacofAcceleration parse_smacof_acceleration(const std::string& name) {
    for (SmacofAcceleration a :
         {SmacofAcceleration::None, SmacofAcceleration::Relaxed, SmacofAcceleration::Rre,
          SmacofAcceleration::Mpe, SmacofAcceleration::Anderson})
        if (name == to_string(a)) return a;
    throw InputError("unknown SMACOF acceleration '" + name + "' (none, relaxed, rre, mpe, anderson)");
}

ParameterSet<SmacofOptions> smacof_parameters(const SmacofOptions& defaults) {
    ParameterSet<SmacofOptions> s(defaults);
    s.add(Parameter::number("tolerance", 0, 1)
              .label("Tolerance")
              .help("SMACOF stops when an iteration lowers the stress by less than this fraction")
              .alias("tol"),
          &SmacofOptions::tolerance);
    s.add(Parameter::integer("max_iterations", 1, 1e7)
              .label("Maximum iterations")
              .help("SMACOF iteration cap")
              .alias("max-iter"),
          &SmacofOptions::max_iterations);
    s.add(Parameter::choice("acceleration", smacof_acceleration_names())
              .label("SMACOF acceleration")
              .help("SMACOF acceleration: none (plain Guttman steps), relaxed (X + 2(G(X) - X), de Leeuw), "
                    "rre or mpe "
                    "(reduced-rank or minimal-polynomial vector extrapolation, Rosman et al. 2008), anderson "
                    "(Anderson "
                    "acceleration); a step that would raise the stress is replaced by the plain step"),
          &SmacofOptions::acceleration);
    return s;
}

namespace {

double dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a.array() * b.array()).sum();
}

/// Solves the small symmetric positive semi-definite system G x = b with a ridge of 1e-12 trace(G).
Eigen::VectorXd solve_gram(Eigen::MatrixXd G, const Eigen::VectorXd& b) {
    const double ridge = 1e-12 * std::max(G.trace(), 1e-300);
    G.diagonal().array() += ridge;
    return G.ldlt().solve(b);
}

}  // namespace

GuttmanAccelerator::GuttmanAccelerator(SmacofAcceleration method, int depth)
    : method_(method), depth_(depth) {
    if (depth_ < 1) throw InputError("SMACOF: the acceleration depth must be at least 1");
}

void GuttmanAccelerator::rejected() {
    dF_.clear();
    dG_.clear();
}

Eigen::MatrixXd GuttmanAccelerator::propose(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                            bool* extrapolated) {
    *extrapolated = false;
    const bool forced = plain_next_;
    plain_next_ = false;
    switch (method_) {
        case SmacofAcceleration::None:
            return Y;
        case SmacofAcceleration::Relaxed:
            // Every other step: the relaxed update alone oscillates on the fast modes (see the header).
            relax_next_ = !relax_next_ && !forced;
            if (!relax_next_) return Y;
            *extrapolated = true;
            return 2 * Y - X;
        case SmacofAcceleration::Rre:
        case SmacofAcceleration::Mpe: {
            // Inside a cycle every step is plain: x_{j+1} = G(x_j), u_j = G(x_j) - x_j.
            if (U_.empty()) x0_ = X;
            U_.push_back(Y - X);
            const int k = static_cast<int>(U_.size()) - 1;
            gram_.conservativeResize(k + 1, k + 1);
            for (int a = 0; a <= k; ++a)
                gram_(a, k) = gram_(k, a) = dot(U_[static_cast<size_t>(a)], U_[static_cast<size_t>(k)]);
            if (k < depth_) return Y;
            const int K = depth_;  // u_0 .. u_K
            Eigen::VectorXd gamma(K + 1);
            if (method_ == SmacofAcceleration::Rre) {
                gamma = solve_gram(gram_, Eigen::VectorXd::Ones(K + 1));
            } else {
                gamma.head(K) = solve_gram(gram_.topLeftCorner(K, K), -gram_.col(K).head(K));
                gamma(K) = 1;
            }
            const double sum = gamma.sum();
            Eigen::MatrixXd Z;
            if (gamma.allFinite() && std::isfinite(sum) && std::abs(sum) > 1e-300) {
                gamma /= sum;
                // sum_j gamma_j x_{j+1} = x_0 + sum_i (sum_{j >= i} gamma_j) u_i
                Z = x0_;
                double tail = 0;
                for (int i = K; i >= 0; --i) {
                    tail += gamma(i);
                    Z += tail * U_[static_cast<size_t>(i)];
                }
                *extrapolated = true;
            } else {
                Z = Y;
            }
            U_.clear();
            gram_.resize(0, 0);
            return Z;
        }
        case SmacofAcceleration::Anderson: {
            Eigen::MatrixXd f = Y - X;
            if (f_prev_.size()) {
                dF_.push_back(f - f_prev_);
                dG_.push_back(Y - g_prev_);
                if (static_cast<int>(dF_.size()) > depth_) {
                    dF_.erase(dF_.begin());
                    dG_.erase(dG_.begin());
                }
            }
            f_prev_ = f;
            g_prev_ = Y;
            if (dF_.empty() || forced) return Y;
            const int m = static_cast<int>(dF_.size());
            Eigen::MatrixXd G(m, m);
            Eigen::VectorXd b(m);
            for (int a = 0; a < m; ++a) {
                b(a) = dot(dF_[static_cast<size_t>(a)], f);
                for (int c = a; c < m; ++c)
                    G(a, c) = G(c, a) = dot(dF_[static_cast<size_t>(a)], dF_[static_cast<size_t>(c)]);
            }
            const Eigen::VectorXd gamma = solve_gram(G, b);
            if (!gamma.allFinite()) return Y;
            Eigen::MatrixXd Z = Y;
            for (int a = 0; a < m; ++a) Z -= gamma(a) * dG_[static_cast<size_t>(a)];
            *extrapolated = true;
            return Z;
        }
    }
    return Y;
}

SmacofSolver::SmacofSolver(int num_points, StressPairs pairs, const SmacofSolverOptions& options)
    : n_(num_points), pairs_(std::move(pairs)), options_(options) {
    if (n_ < 2) throw InputError("SMACOF needs at least two points");
    if (options_.vcycles_per_step < 1)
        throw InputError("SMACOF: vcycles_per_step must be at least 1 (given " +
                         std::to_string(options_.vcycles_per_step) + ")");
    const size_t m = pairs_.size();
    Eigen::MatrixXi E(static_cast<Eigen::Index>(m), 2);
    for (size_t k = 0; k < m; ++k) {
        const int a = pairs_.i[k], b = pairs_.j[k];
        const double w = pairs_.w[k], d = pairs_.delta[k];
        if (a < 0 || b < 0 || a >= n_ || b >= n_ || a == b)
            throw InputError("SMACOF: a pair has an index out of range or joins a point to itself");
        if (!(w > 0) || !std::isfinite(w) || !(d >= 0) || !std::isfinite(d))
            throw InputError("SMACOF: weights must be positive and targets non-negative and finite");
        E(static_cast<Eigen::Index>(k), 0) = a;
        E(static_cast<Eigen::Index>(k), 1) = b;
    }
    int components = 0;
    connected_components(n_, E, &components);
    E.resize(0, 2);
    if (components != 1) {
        std::ostringstream msg;
        msg << "SMACOF: the weighted pairs split the points into " << components
            << " groups; the configuration would not be determined";
        throw InputError(msg.str());
    }
    // V of the pinned system (vertex 0's row and column dropped, indices shift by one), straight
    // into compressed storage (no triplet list: 4 x 16 bytes per pair, 190 MB at 1M vertices),
    // column by column: column v - 1 sums, in pair order, +w on its diagonal and -w in row u - 1
    // for every pair (v, u) with u > 0, each entry starting from 0 (the order in which
    // setFromTriplets() summed them, so V is the same to the bit; sparse_columns.h), the columns
    // shared out on large meshes. first[c] .. first[c + 1]: the pairs of column c, in order.
    std::vector<int> first(static_cast<size_t>(n_), 0);
    for (size_t k = 0; k < m; ++k) {
        if (pairs_.i[k] > 0) ++first[static_cast<size_t>(pairs_.i[k])];
        if (pairs_.j[k] > 0) ++first[static_cast<size_t>(pairs_.j[k])];
    }
    for (int c = 0; c + 1 < n_; ++c) first[static_cast<size_t>(c) + 1] += first[static_cast<size_t>(c)];
    std::vector<int> column_pairs(static_cast<size_t>(first.back()));
    {
        std::vector<int> next(first.begin(), first.end() - 1);
        for (size_t k = 0; k < m; ++k) {
            const int a = pairs_.i[k], b = pairs_.j[k];
            if (a > 0)
                column_pairs[static_cast<size_t>(next[static_cast<size_t>(a - 1)]++)] = static_cast<int>(k);
            if (b > 0)
                column_pairs[static_cast<size_t>(next[static_cast<size_t>(b - 1)]++)] = static_cast<int>(k);
        }
    }
    const Eigen::SparseMatrix<double> Vr =
        assemble_columns(n_ - 1, n_ - 1, options_.threads, [&](Eigen::Index c, ColumnEntries& column) {
            for (int p = first[static_cast<size_t>(c)]; p < first[static_cast<size_t>(c) + 1]; ++p) {
                const size_t k = static_cast<size_t>(column_pairs[static_cast<size_t>(p)]);
                const int a = pairs_.i[k], b = pairs_.j[k];
                const int other = a == c + 1 ? b : a;
                column.add(static_cast<int>(c), pairs_.w[k]);
                if (other > 0) column.add(other - 1, -pairs_.w[k]);
            }
        });
    multigrid_ = use_multigrid(options_.linear_solver, n_, options_.multigrid_from);
    if (multigrid_) {
        AmgOptions amg;
        amg.threads = options_.threads;
        amg_ = AmgPreconditioner(Vr, amg);
    } else if (!factor_.compute(Vr, options_.ordering)) {
        throw NumericalError("SMACOF: the Cholesky factorisation of V failed");
    }
}

double SmacofSolver::stress(const Eigen::MatrixXd& X) const {
    double s = 0;
    guttman_rhs(X, nullptr, &s);
    return s;
}

namespace {

// The pair (a, c)'s term of B(X) X: row a gains f t, row c loses it (rows of four doubles, see rhs3).
inline void add_pair_term(double* b4, std::ptrdiff_t a, std::ptrdiff_t c, double f, const v4d& t) {
    const v4d ft = f * t;
    store4d(b4 + a, load4d(b4 + a) + ft);
    store4d(b4 + c, load4d(b4 + c) - ft);
}

// |t|^2 of a difference of two rows of four (the fourth lane 0 and left out), summed over the
// coordinates in order from 0 as the general loop sums it.
inline double squared_length3(const v4d& t) {
    const v4d t2 = t * t;
    double d2 = 0;
    d2 += t2[0];
    d2 += t2[1];
    d2 += t2[2];
    return d2;
}

// guttman_rhs() of three-dimensional points, each point's coordinates side by side in four doubles
// (x4[4i + c], the fourth 0): a pair reads two 32-byte rows instead of six scattered values, and
// its differences, squares and updates of B(X) X (b4, the same layout; null: the stress alone) are
// per-lane vector operations. Every value is the same IEEE operations in the same order as the
// general loop: d^2 summed over the coordinates in order, the stress summed over the pairs in order,
// each point's row of B(X) X updated pair after pair.
CANONFORM_CLONES double rhs3(const int* I, const int* J, const double* delta, const double* w, size_t pairs,
                             const double* x4, double* b4) {
    double s = 0;
    size_t k = 0;
    // Four pairs at a time: their square roots and divisions, the slow part, as vector operations
    // (one lane per pair); the stress and B(X) X then summed pair after pair as below.
    for (; k + 4 <= pairs; k += 4) {
        v4d t[4], d2;
        for (int u = 0; u < 4; ++u) {
            const std::ptrdiff_t a = static_cast<std::ptrdiff_t>(I[k + u]) * 4;
            const std::ptrdiff_t c = static_cast<std::ptrdiff_t>(J[k + u]) * 4;
            t[u] = load4d(x4 + a) - load4d(x4 + c);
            d2[u] = squared_length3(t[u]);
        }
        v4d d;
        for (int u = 0; u < 4; ++u) d[u] = std::sqrt(d2[u]);
        const v4d dk = load4d(delta + k), wk = load4d(w + k);
        const v4d r = dk - d;
        const v4d wrr = wk * r * r;
        const v4d f = wk * dk / d;  // -b_ac of eq. (3); unused where d = 0
        for (int u = 0; u < 4; ++u) s += wrr[u];
        if (!b4) continue;
        for (int u = 0; u < 4; ++u) {
            if (d[u] > 0)
                add_pair_term(b4, static_cast<std::ptrdiff_t>(I[k + u]) * 4,
                              static_cast<std::ptrdiff_t>(J[k + u]) * 4, f[u], t[u]);
        }
    }
    for (; k < pairs; ++k) {
        const std::ptrdiff_t a = static_cast<std::ptrdiff_t>(I[k]) * 4,
                             c = static_cast<std::ptrdiff_t>(J[k]) * 4;
        const v4d t = load4d(x4 + a) - load4d(x4 + c);
        const double d = std::sqrt(squared_length3(t));
        const double r = delta[k] - d;
        s += w[k] * r * r;
        if (b4 && d > 0) add_pair_term(b4, a, c, w[k] * delta[k] / d, t);  // f = -b_ac of eq. (3)
    }
    return s;
}

}  // namespace

void SmacofSolver::guttman_rhs(const Eigen::MatrixXd& X, Eigen::MatrixXd* BX, double* stress_of_X,
                               std::vector<double>* scratch) const {
    const Eigen::Index n = X.rows(), dim = X.cols();
    const double* x = X.data();
    if (dim == 3) {
        std::vector<double> local;
        std::vector<double>& room = scratch ? *scratch : local;
        room.resize(static_cast<size_t>(n) * (BX ? 8 : 4));
        double* x4 = room.data();
        double* b4 = BX ? x4 + 4 * n : nullptr;
        for (Eigen::Index i = 0; i < n; ++i) {
            x4[4 * i] = x[i];
            x4[4 * i + 1] = x[n + i];
            x4[4 * i + 2] = x[2 * n + i];
            x4[4 * i + 3] = 0;
        }
        if (b4) std::fill(b4, b4 + 4 * n, 0.0);
        const double s = rhs3(pairs_.i.data(), pairs_.j.data(), pairs_.delta.data(), pairs_.w.data(),
                              pairs_.size(), x4, b4);
        if (BX) {
            BX->resize(n, 3);
            double* b = BX->data();
            for (Eigen::Index i = 0; i < n; ++i) {
                b[i] = b4[4 * i];
                b[n + i] = b4[4 * i + 1];
                b[2 * n + i] = b4[4 * i + 2];
            }
        }
        if (stress_of_X) *stress_of_X = s;
        return;
    }
    // Column-major X: coordinate c of point i is x[c * n + i]. Plain loops, no temporaries: this
    // is the O(#pairs) half of every iteration.
    double* b = nullptr;
    if (BX) {
        BX->setZero(n, dim);
        b = BX->data();
    }
    double s = 0;
    double diff[8];
    const bool small = dim <= 8;
    for (size_t k = 0; k < pairs_.size(); ++k) {
        const Eigen::Index a = pairs_.i[k], c = pairs_.j[k];
        double d2 = 0;
        for (Eigen::Index q = 0; q < dim; ++q) {
            const double t = x[q * n + a] - x[q * n + c];
            if (small) diff[q] = t;
            d2 += t * t;
        }
        const double d = std::sqrt(d2);
        const double r = pairs_.delta[k] - d;
        s += pairs_.w[k] * r * r;
        if (b && d > 0) {
            const double f = pairs_.w[k] * pairs_.delta[k] / d;  // -b_ac of eq. (3)
            for (Eigen::Index q = 0; q < dim; ++q) {
                const double t = small ? diff[q] : x[q * n + a] - x[q * n + c];
                b[q * n + a] += f * t;
                b[q * n + c] -= f * t;
            }
        }
    }
    if (stress_of_X) *stress_of_X = s;
}

Eigen::MatrixXd SmacofSolver::guttman(const Eigen::MatrixXd& X, double* stress_of_X) const {
    StepWorkspace work;
    return guttman(X, stress_of_X, work);
}

Eigen::MatrixXd SmacofSolver::guttman(const Eigen::MatrixXd& X, double* stress_of_X,
                                      StepWorkspace& work) const {
    Eigen::MatrixXd& BX = work.BX;
    guttman_rhs(X, &BX, stress_of_X, &work.interleaved);
    Eigen::MatrixXd Y(n_, X.cols());
    Y.row(0).setZero();
    if (multigrid_) {
        // Warm start at X translated so that the pinned vertex 0 sits at the origin.
        const Eigen::RowVectorXd origin = X.row(0);
        parallel_rows(n_, options_.threads, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index c = 0; c < X.cols(); ++c)
                for (Eigen::Index i = std::max<Eigen::Index>(begin, 1); i < end; ++i)
                    Y(i, c) = X(i, c) - origin(c);
        });
        amg_.cycle(BX.bottomRows(n_ - 1), Y.bottomRows(n_ - 1), options_.vcycles_per_step, work.amg);
        if (!Y.allFinite())
            throw NumericalError("SMACOF: the multigrid solve of V produced non-finite values");
    } else {
        Y.bottomRows(n_ - 1) = factor_.solve(BX.bottomRows(n_ - 1));
        if (!factor_.ok()) throw NumericalError("SMACOF: the solve with the factor of V failed");
    }
    const Eigen::RowVectorXd mean = Y.colwise().mean();
    parallel_rows(n_, options_.threads, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index c = 0; c < Y.cols(); ++c)
            for (Eigen::Index i = begin; i < end; ++i) Y(i, c) -= mean(c);
    });
    return Y;
}

SmacofResult SmacofSolver::solve(const Eigen::MatrixXd& X0, const SmacofOptions& options) const {
    if (X0.rows() != n_ || X0.cols() < 1) throw InputError("SMACOF: the start has the wrong shape");
    if (!X0.allFinite()) throw InputError("SMACOF: the start has non-finite coordinates");
    StepWorkspace work;
    return run_guttman([this, &work](const Eigen::MatrixXd& X, double* s) { return guttman(X, s, work); },
                       X0.rowwise() - X0.colwise().mean(), options, "SMACOF");
}

}  // namespace canonform::numerics
