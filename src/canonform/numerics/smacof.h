// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: weighted SMACOF (stress majorisation) on a sparse set of pairs.
//
// Reference: Pickup et al., Pattern Recognition 2015, eqs. (1)-(6); J. de Leeuw, "Applications of
// convex analysis to multidimensional scaling", 1977; A. Elad and R. Kimmel, "On bending invariant
// signatures for surfaces", IEEE TPAMI 2003.
//
//   (1) S(X) = sum_{i<j} w_ij (delta_ij - d_ij(X))^2          (only the given pairs: w = 0 elsewhere)
//   (2) X_k = V^+ B(X_{k-1}) X_{k-1}                           (the Guttman transform)
//   (3) b_ij = -w_ij delta_ij / d_ij(X) for d_ij != 0, else 0
//   (4) b_ii = -sum_{j != i} b_ij
//   (5,6) V = sum_{i<j} w_ij (e_i - e_j)(e_i - e_j)^T         (a weighted graph Laplacian)
//
// Departures from the paper, and why:
// - Eq. (4) is printed as b_ii = +sum_{j != i} b_ij; the majorisation needs the minus sign
//   (rows of B sum to zero, as in de Leeuw and Elad-Kimmel). We use the minus sign.
// - V^+ is never formed: V is constant, so we set up its solver once after pinning one vertex
//   (dropping its row and column, which makes V positive definite when the pair graph is
//   connected), solve, and re-centre. Because 1^T B X = 0 this equals V^+ B X exactly.
//   B(X) X is accumulated pair by pair, O(#pairs).
// - Two solvers of V Y = B(X) X (SmacofSolverOptions): a sparse LDL^T factor (exact; fastest
//   while the factor fits in cache, below ~40k points), or, from there, one V-cycle of algebraic
//   multigrid (algebraic_multigrid.h) started at X: O(#pairs) per step, so an iteration stays
//   linear in N as the paper's Section 5 counts it, where the factor's fill grows faster (~N log N)
//   and leaves the cache. The inexact step keeps the majorisation: every part of a V-cycle
//   minimises the majorising quadratic tau(Y, X) over a subspace through the current Y, so from
//   Y = X it ends below tau(X, X) = S(X) and S never increases either way. It converges in about
//   10-20% more iterations, to the same configuration within the stopping rule's own spread
//   (measured in bench/run_bench.sh: both solvers side by side).
// - The stopping rule is relative: stop when (S_{k-1} - S_k) / S_{k-1} < tolerance, or after
//   max_iterations; the paper's absolute rule S_{k-1} - S_k < e depends on the mesh's scale.
// Stress never increases across a Guttman step (tested).
//
// Acceleration (SmacofAcceleration; every SMACOF run: Euclidean canonical forms and least-squares
// MDS). The Guttman iteration converges linearly, slowly on meshes (docs/benchmarks.md). Methods:
// - none: plain Guttman steps, eq. (2).
// - relaxed: J. de Leeuw and W. Heiser, "Convergence of correction matrix algorithms for
//   multidimensional scaling", 1980: X + 2 (G(X) - X). The majorising quadratic tau(., X) is
//   symmetric about its minimiser G(X), so S(2G(X) - X) <= tau(X, X) = S(X).
//   Departure: applied every other step, a plain step between. Alone it maps an error mode with
//   Guttman rate lambda to rate 2 lambda - 1, which is about -1 for the fast modes: they never
//   decay, and the stress stalled far above the plain run's (the sparse problem of
//   tests/test_smacof.cpp). Alternating gives lambda (2 lambda - 1), in [-1/8, 1].
// - rre, mpe: G. Rosman, A. M. Bronstein, M. M. Bronstein, R. Kimmel, "Fast multidimensional
//   scaling using vector extrapolation", 2008 (after A. Sidi's reduced-rank and minimal-polynomial
//   extrapolation): every `acceleration_depth` + 1 plain steps x_0..x_K, x_{K+1} = G(x_K), with
//   u_j = x_{j+1} - x_j and U = [u_0 .. u_K], the next point is sum_j gamma_j x_{j+1} with
//   RRE: gamma = argmin |U gamma| subject to sum gamma = 1, i.e. (U^T U)^-1 1 normalised;
//   MPE: gamma = (c, 1) / sum (c, 1), c = argmin |U_{0..K-1} c + u_K|.
//   Departures: the sum uses x_{j+1} (one Guttman step further than Sidi's x_j, which costs
//   nothing: G(x_K) is known); the small Gram systems U^T U are solved with a ridge of 1e-12 of
//   their trace (LDL^T).
// - anderson: D. G. Anderson, "Iterative procedures for nonlinear integral equations", 1965, type
//   II with memory m = acceleration_depth (H. F. Walker and P. Ni, SIAM J. Numer. Anal. 2011):
//   f_k = G(x_k) - x_k, x_{k+1} = G(x_k) - dG gamma with gamma = argmin |f_k - dF gamma| over the
//   last m differences; history cleared when the safeguard fires.
// Monotone safeguard, every method: an extrapolated point whose stress exceeds the stress of the
// current iterate is rejected and the plain Guttman step taken instead, so S never increases
// (tested per method). The stopping rule is tested on plain steps only (an extrapolation that
// gains less than the tolerance is followed by a plain step). Every evaluation of S and B(X) X
// (one pass over the pairs and one solve), rejected ones included, counts as an iteration, so
// iteration counts compare costs.
#pragma once

#include "canonform/common/errors.h"
#include "canonform/common/parameters.h"
#include "canonform/numerics/algebraic_multigrid.h"
#include "canonform/numerics/sparse_cholesky.h"

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace canonform::numerics {

/// The pairs (i, j) of eq. (1) with their target distance delta and weight w (> 0).
struct StressPairs {
    std::vector<int> i, j;
    std::vector<double> delta, w;
    void add(int a, int b, double target, double weight) {
        i.push_back(a);
        j.push_back(b);
        delta.push_back(target);
        w.push_back(weight);
    }
    size_t size() const { return i.size(); }
};

/// How the Guttman iteration is accelerated (see the top of this header).
enum class SmacofAcceleration { None, Relaxed, Rre, Mpe, Anderson };

/// The default acceleration of every SMACOF run (chosen by bench/run_bench_acceleration.sh: see
/// docs/benchmarks.md, "SMACOF acceleration").
constexpr SmacofAcceleration kDefaultSmacofAcceleration = SmacofAcceleration::Rre;
/// Default depth: RRE/MPE plain steps per extrapolation minus one; Anderson memory.
constexpr int kDefaultAccelerationDepth = 2;

/// "none", "relaxed", "rre", "mpe", "anderson".
const char* to_string(SmacofAcceleration a);
/// The inverse of to_string(); InputError listing the names for anything else.
SmacofAcceleration parse_smacof_acceleration(const std::string& name);
/// Every method's name, in enum order.
std::vector<std::string> smacof_acceleration_names();

/// Options of a SMACOF iteration: SmacofSolver::solve(), least-squares MDS (mds.h) and every
/// method built on them, whose options hold one SmacofOptions (never a copy of its fields).
struct SmacofOptions {
    double tolerance = 1e-5;    ///< relative stress decrease below which iteration stops
    int max_iterations = 1000;  ///< iteration cap (every stress evaluation counts)
    SmacofAcceleration acceleration = kDefaultSmacofAcceleration;  ///< see the top of this header
    int acceleration_depth = kDefaultAccelerationDepth;  ///< RRE/MPE cycle - 1, Anderson memory (>= 1)
    bool record_history = false;  ///< keep S(X_k) for every k in SmacofResult::stress_history
    ProgressFn progress;          ///< called every few iterations (fraction of max_iterations)

    /// Named setters, for a default other than the ones above (`SmacofOptions().with_max_iterations(500)`).
    SmacofOptions& with_tolerance(double t) {
        tolerance = t;
        return *this;
    }
    SmacofOptions& with_max_iterations(int n) {
        max_iterations = n;
        return *this;
    }
    SmacofOptions& with_acceleration(SmacofAcceleration a) {
        acceleration = a;
        return *this;
    }
};

/// The parameters of SmacofOptions a user sets - tolerance, max_iterations, acceleration - with
/// their defaults from `defaults` (common/parameters.h: the method registry, the filters, the tool
/// and the docs derive from them).
ParameterSet<SmacofOptions> smacof_parameters(const SmacofOptions& defaults = {});

/// What a SMACOF run reports: counts and stresses. Every result that reports a run derives from
/// it (SmacofResult, MdsResult, the canonical forms' results), so one assignment passes it on.
struct SmacofStatistics {
    int iterations = 0;                  ///< stress evaluations after the start (rejected ones included)
    bool converged = false;              ///< stopped by the tolerance, not by the cap
    int extrapolations = 0;              ///< accelerated points accepted
    int rejections = 0;                  ///< accelerated points replaced by the plain step (safeguard)
    double initial_stress = 0;           ///< S(X_0)
    double final_stress = 0;             ///< S(X_final)
    std::vector<double> stress_history;  ///< S of every accepted iterate X_0, X_1, ... if requested
};

/// Result of SmacofSolver::solve() and run_guttman().
struct SmacofResult : SmacofStatistics {
    Eigen::MatrixXd X;  ///< final configuration, #V x dim, centred at the origin
};

/// Proposes the next point of an accelerated Guttman iteration (see the top of this header).
class GuttmanAccelerator {
public:
    GuttmanAccelerator(SmacofAcceleration method, int depth);
    /// The next point to evaluate after iterate X with Guttman transform Y = G(X): Y itself
    /// (*extrapolated = false) or an extrapolation (true).
    Eigen::MatrixXd propose(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, bool* extrapolated);
    /// The last extrapolation raised the stress and was replaced by the plain step.
    void rejected();
    /// The next proposal is the plain step (the stopping rule is tested on plain steps only).
    void plain_next() { plain_next_ = true; }

private:
    SmacofAcceleration method_;
    int depth_;
    Eigen::MatrixXd x0_;                    // RRE/MPE: x_0 of the current cycle
    std::vector<Eigen::MatrixXd> U_;        // RRE/MPE: u_j = x_{j+1} - x_j of the current cycle
    Eigen::MatrixXd gram_;                  // RRE/MPE: U^T U, grown a row per step
    std::vector<Eigen::MatrixXd> dF_, dG_;  // Anderson: differences of f and G
    Eigen::MatrixXd f_prev_, g_prev_;       // Anderson: the previous f and G(x)
    bool relax_next_ = false;               // relaxed: this step relaxes
    bool plain_next_ = false;               // plain_next() was called
};

/// The SMACOF iteration shared by SmacofSolver::solve and least_squares_mds (mds.h): from a
/// centred start X, `step(X, &s)` returns the Guttman transform of X and sets s = S(X). Stops when
/// S_{k-1} - S_k < options.tolerance * S_{k-1} on a plain step, or after options.max_iterations
/// evaluations of `step` after the first (none if <= 0). Accelerated by options.acceleration with
/// the monotone safeguard (top of this header). Progress goes to options.progress from
/// `progress_from` to 1. `what` names the solver in error messages.
template <class Step>
SmacofResult run_guttman(const Step& step, Eigen::MatrixXd X, const SmacofOptions& options, const char* what,
                         double progress_from = 0.0) {
    const double tolerance = options.tolerance;
    const int max_iterations = options.max_iterations;
    const bool record_history = options.record_history;
    const ProgressFn& progress = options.progress;
    SmacofResult r;
    GuttmanAccelerator accelerator(options.acceleration, options.acceleration_depth);
    const auto evaluate = [&](const Eigen::MatrixXd& Z, double* s) {
        Eigen::MatrixXd G = step(Z, s);  // S(Z) comes with the step's B(Z) Z
        if (!std::isfinite(*s) || !G.allFinite())
            throw NumericalError(std::string(what) +
                                 ": non-finite stress or coordinates after a Guttman step");
        ++r.iterations;
        if (r.iterations % 10 == 0)
            report_progress(progress, progress_from + (1 - progress_from) * r.iterations / max_iterations,
                            "SMACOF iterations");
        return G;
    };
    double s_x = 0;
    Eigen::MatrixXd Y = step(X, &s_x);
    if (!std::isfinite(s_x) || !Y.allFinite())
        throw NumericalError(std::string(what) + ": non-finite stress or coordinates after a Guttman step");
    r.initial_stress = r.final_stress = s_x;
    if (record_history) r.stress_history.push_back(s_x);
    while (r.iterations < max_iterations) {
        bool extrapolated = false;
        Eigen::MatrixXd Z = accelerator.propose(X, Y, &extrapolated);
        double s = 0;
        Eigen::MatrixXd GZ = evaluate(Z, &s);
        if (extrapolated && !(s <= s_x)) {  // safeguard: the plain step instead
            accelerator.rejected();
            ++r.rejections;
            extrapolated = false;
            if (r.iterations >= max_iterations) break;
            Z = std::move(Y);
            GZ = evaluate(Z, &s);
        } else if (extrapolated) {
            ++r.extrapolations;
        }
        if (record_history) r.stress_history.push_back(s);
        r.final_stress = s;
        // The stopping rule is tested on plain steps only: an extrapolation that gains less than
        // the tolerance is followed by a plain step, which decides.
        const bool small = (s_x - s) < tolerance * s_x;
        r.converged = s_x <= 0 || (!extrapolated && small);
        if (extrapolated && small) accelerator.plain_next();
        X = std::move(Z);
        Y = std::move(GZ);
        s_x = s;
        if (r.converged) break;
    }
    r.X = std::move(X);  // Y (one step further) is discarded so that final_stress is exactly S(r.X)
    return r;
}

/// Options of the SmacofSolver constructor.
struct SmacofSolverOptions {
    LinearSolver linear_solver = LinearSolver::Auto;
    int multigrid_from = kMultigridFrom;  ///< Auto: points from which Multigrid is used
    int vcycles_per_step = 1;             ///< Multigrid: V-cycles per Guttman step (>= 1)
    /// Direct: fill-reducing ordering of V with point 0 pinned (num_points - 1 entries, entry
    /// k = point ordering[k] + 1 eliminated k-th; see SparseCholesky::compute); empty = AMD.
    std::vector<int> ordering;
    int threads = 0;  ///< Multigrid: threads of its large sweeps (AmgOptions::threads; no effect on results)
};

/// Weighted SMACOF for a fixed set of pairs: builds and factors V once, then iterates Guttman
/// transforms from any start. Throws InputError if the pair graph does not connect all vertices
/// or a weight/target is negative or non-finite, NumericalError if the factorisation fails.
class SmacofSolver {
public:
    SmacofSolver(int num_points, StressPairs pairs, const SmacofSolverOptions& options = {});

    /// Runs SMACOF from X0 (#points x dim, any dim >= 1).
    SmacofResult solve(const Eigen::MatrixXd& X0, const SmacofOptions& options = {}) const;

    /// S(X) of eq. (1).
    double stress(const Eigen::MatrixXd& X) const;

    /// One Guttman transform X -> V^+ B(X) X (eq. 2), re-centred at the origin. If `stress_of_X`
    /// is given, S(X) is returned in it (computed in the same pass).
    Eigen::MatrixXd guttman(const Eigen::MatrixXd& X, double* stress_of_X = nullptr) const;

    int num_points() const { return n_; }
    /// The solver in use: Direct or Multigrid (never Auto).
    LinearSolver linear_solver() const { return multigrid_ ? LinearSolver::Multigrid : LinearSolver::Direct; }

private:
    /// B(X) X (#points x dim, if BX is given) and S(X) (if stress_of_X is given), in one pass.
    /// `scratch`: room for three-dimensional X and B(X) X with each point's coordinates side by
    /// side (sized here; a local one if null).
    void guttman_rhs(const Eigen::MatrixXd& X, Eigen::MatrixXd* BX, double* stress_of_X,
                     std::vector<double>* scratch = nullptr) const;
    /// What a Guttman step works in, kept for all steps of one solve(): no n x dim allocations
    /// per step (large ones are faulted in again every step when freed memory goes back to the
    /// system; docs/benchmarks.md, "Canonical form at scale").
    struct StepWorkspace {
        Eigen::MatrixXd BX;
        std::vector<double> interleaved;  // guttman_rhs()'s scratch
        AmgPreconditioner::Workspace amg;
    };
    Eigen::MatrixXd guttman(const Eigen::MatrixXd& X, double* stress_of_X, StepWorkspace& work) const;

    int n_;
    StressPairs pairs_;
    SmacofSolverOptions options_;
    bool multigrid_ = false;
    SparseCholesky factor_;  // Direct: V with vertex 0 pinned
    AmgPreconditioner amg_;  // Multigrid: the same matrix
};

}  // namespace canonform::numerics
