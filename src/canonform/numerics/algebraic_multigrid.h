// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: smoothed-aggregation algebraic multigrid (AMG) as a preconditioner for conjugate
// gradients, for the large sparse symmetric positive definite systems of the core (SMACOF's V).
//
// References: P. Vanek, J. Mandel, M. Brezina, "Algebraic multigrid by smoothed aggregation for
// second and fourth order elliptic problems", Computing 56, 1996 (aggregation, smoothed
// prolongator P = (I - omega D^-1 A) P_tent, Galerkin coarse operator P^T A P); W. L. Briggs,
// V. E. Henson, S. F. McCormick, "A multigrid tutorial", 2nd ed., SIAM 2000 (V-cycle, symmetric
// Gauss-Seidel smoothing); Y. Saad, "Iterative methods for sparse linear systems", 2nd ed., SIAM
// 2003, Alg. 9.1 (preconditioned CG).
//
// Why: the paper (Section 5) counts one SMACOF iteration as O(N). With a sparse LDL^T factor of V
// the two triangular solves per iteration cost O(nnz(L)), which grows faster than N (fill ~N log N
// with a fill-reducing ordering) and leaves the cache beyond a few 10k vertices (measured by
// bench/run_bench.sh; docs/benchmarks.md). A V-cycle costs a few sweeps over A (7 entries per row) per
// level, O(N) in all, and CG with it needs a number of steps that does not grow with N.
//
// Departure, for threads: on a level of 1M non-zeros or more (a mesh from about 140k vertices) the
// Gauss-Seidel sweeps visit the rows chunk by chunk (16384 rows each), the chunks coloured so that
// no two chunks of one colour couple, one colour after another, and the chunks of a colour run on
// every thread. That is Gauss-Seidel in another fixed order of the rows (the backward sweep its
// exact reverse), so every property above holds and the bits do not depend on the threads; the
// products of such levels run their row chunks on every thread too. Smaller levels keep the
// natural order on the calling thread (no pool for small work).
//
// Conventions: A is symmetric positive definite (callers pin one vertex of a graph Laplacian).
// Right-hand sides and solutions are #rows x k matrices (k columns solved together: each pass over
// the matrix serves all k). The coarsest level (<= coarse_size rows) is solved by sparse Cholesky.
#pragma once

#include "canonform/numerics/sparse_cholesky.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <string>
#include <vector>

namespace canonform::numerics {

/// How a core algorithm solves its large sparse SPD systems (SMACOF's V, the conformal factor's
/// Laplacian).
enum class LinearSolver {
    Auto,       ///< Direct below kMultigridFrom unknowns, Multigrid from there
    Direct,     ///< sparse LDL^T factor (sparse_cholesky.h): exact, fastest while it fits in cache
    Multigrid,  ///< this header: O(N) per solve or step
};

/// Size from which LinearSolver::Auto picks Multigrid: where the two meet on this project's
/// meshes (bench/run_bench.sh: equal at 10k vertices, multigrid 0.6x the time at 50k and 200k).
constexpr int kMultigridFrom = 40000;

/// Name of a linear solver ("auto", "direct", "multigrid").
const char* to_string(LinearSolver s);
/// Every solver's name, in LinearSolver's order (a parameter's choices).
std::vector<std::string> linear_solver_names();

struct AmgOptions;

/// True if `s` means multigrid for a system of `unknowns` rows. A system no larger than AMG's
/// coarsest level is solved directly whatever `s` says (a one-level hierarchy is a direct solve).
bool use_multigrid(LinearSolver s, long long unknowns, long long threshold = kMultigridFrom);

/// Options of AmgPreconditioner.
struct AmgOptions {
    double strength = 0.08;  ///< j is a strong neighbour of i if |a_ij| >= strength sqrt(a_ii a_jj)
    int coarse_size = 1500;  ///< levels stop at or below this many rows (then a direct solve)
    int max_levels = 25;     ///< level cap
    int smoothing_sweeps =
        1;  ///< Gauss-Seidel sweeps before (forward) and after (backward) the coarse correction
    /// Threads of the sweeps and products over 1M non-zeros or more (0: every core; smaller ones
    /// run on the calling thread). The results do not depend on it.
    int threads = 0;
};

/// Result of AmgPreconditioner::pcg().
struct PcgReport {
    int iterations = 0;            ///< CG steps taken (every column steps together)
    double relative_residual = 0;  ///< max over columns of |b - A x| / |b - A x0|
    bool converged = false;        ///< relative_residual <= the requested tolerance
};

/// Smoothed-aggregation AMG hierarchy of one SPD matrix; apply() is one symmetric V-cycle (an SPD
/// preconditioner), pcg() solves A X = B by CG preconditioned with it. Set up once, solve many
/// times. Throws NumericalError if the coarsest factorisation fails or A has a non-positive
/// diagonal entry.
class AmgPreconditioner {
public:
    AmgPreconditioner() = default;
    explicit AmgPreconditioner(const Eigen::SparseMatrix<double>& A, const AmgOptions& options = {});

    /// Z = M^-1 R (one V-cycle from a zero guess). R, Z: #rows x k, row-major storage.
    using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    void apply(const Block& R, Block& Z) const;

    /// Solves A X = B by preconditioned CG from the guess X (in/out). Stops when every column's
    /// residual has fallen to `tolerance` times its value at the guess, or after max_iterations;
    /// takes at least `min_iterations` steps. Each CG step lowers the energy
    /// x^T A x / 2 - b^T x of every column, so any number of steps improves on the guess.
    PcgReport pcg(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, double tolerance, int max_iterations,
                  int min_iterations = 1) const;

    /// `cycles` V-cycles on A X = B from the guess X (in/out). Every part of a V-cycle (a
    /// Gauss-Seidel row update, the coarse correction) minimises the energy x^T A x / 2 - b^T x
    /// over a subspace through the current x, so the energy never increases.
    void cycle(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, int cycles) const;

    /// The vectors a V-cycle works in, kept between calls by a caller that cycles many times
    /// (SMACOF: one cycle per Guttman step) so that they are not allocated again every time;
    /// each thread needs its own.
    struct Workspace {
        Block b, x;                             // cycle(): B and X in row-major storage
        std::vector<Block> residual, rhs, sol;  // per level
    };
    /// cycle() working in `work`: the same arithmetic, no allocation after the first call.
    void cycle(const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::Ref<Eigen::MatrixXd> X, int cycles,
               Workspace& work) const;

    int rows() const { return levels_.empty() ? 0 : static_cast<int>(levels_[0].A.rows()); }
    int num_levels() const { return static_cast<int>(levels_.size()); }
    /// Sum of the non-zeros of all levels' matrices over those of the finest (cost of a V-cycle
    /// relative to one sweep over A).
    double operator_complexity() const;

private:
    using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
    struct Level {
        RowSparse A;               // this level's operator
        Eigen::VectorXd inv_diag;  // 1 / a_ii
        RowSparse P;               // prolongation to this level from the next coarser one
        RowSparse R;               // P^T
        // Gauss-Seidel order of a level large enough to share (see the .cpp): its row chunks
        // sorted by colour, and where each colour starts in that list; empty: rows in order.
        std::vector<int> chunk_order, colour_start;
    };
    void vcycle(int level, const Block& b, Block& x, bool zero_guess, Workspace& work) const;

    std::vector<Level> levels_;
    int threads_ = 0;
    SparseCholesky coarse_;
    int sweeps_ = 1;
};

}  // namespace canonform::numerics
