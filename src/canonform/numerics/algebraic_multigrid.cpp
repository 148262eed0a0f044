// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/algebraic_multigrid.h"

#include "canonform/common/errors.h"
#include "canonform/common/parallel.h"
#include "canonform/numerics/graph.h"
#include "canonform/numerics/sparse_columns.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace canonform::numerics {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Block = AmgPreconditioner::Block;

constexpr int kManyWeakCouplings = 16;  // mesh rows have ~6 neighbours, all usually strong

// Rows of a matrix split into chunks of kChunkRows; a product or sweep over at least
// kParallelNonZeros entries runs its chunks on every hardware thread (each row is written by one
// chunk only, so the result does not depend on the threads), a smaller one on the calling thread
// alone (no pool for small work: a mesh below about 140k vertices never starts one).
constexpr Eigen::Index kChunkRows = 16384;
constexpr Eigen::Index kParallelNonZeros = 1000000;

template <class Body>
void for_row_chunks(Eigen::Index n, Eigen::Index nonzeros, int threads, const Body& body) {
    parallel_ranges(n, kChunkRows, nonzeros >= kParallelNonZeros, threads, body);
}

// How a row's sum sum_j a_ij x_j is stored: y_i = sum (Set), y_i = b_i - sum (Residual) or
// y_i += sum (Add). The sum is formed first in every case, so the three give the bits of the
// product followed by a separate subtraction or addition.
enum class Store { Set, Residual, Add };

// y (op)= A x for a row-major block x (#cols x k). K > 0: k known at compile time (the common k = 3).
template <int K, Store S>
void multiply_k(const RowSparse& A, const Block& x, Block& y, const Block* b, int threads) {
    const Eigen::Index n = A.rows(), k = K > 0 ? K : x.cols();
    if (S != Store::Add) y.resize(n, k);
    const auto* outer = A.outerIndexPtr();
    const auto* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
    const double* xs = x.data();
    const double* bs = b ? b->data() : nullptr;
    double* ys = y.data();
    for_row_chunks(n, A.nonZeros(), threads, [&](Eigen::Index begin, Eigen::Index end) {
        double small[K > 0 ? K : 8];
        std::vector<double> big(K > 0 || k <= 8 ? 0 : static_cast<size_t>(k));
        double* acc = K > 0 || k <= 8 ? small : big.data();
        for (Eigen::Index i = begin; i < end; ++i) {
            for (Eigen::Index c = 0; c < k; ++c) acc[c] = 0;
            for (auto p = outer[i]; p < outer[i + 1]; ++p) {
                const double a = val[p];
                const double* xj = xs + static_cast<Eigen::Index>(inner[p]) * k;
                for (Eigen::Index c = 0; c < k; ++c) acc[c] += a * xj[c];
            }
            double* yi = ys + i * k;
            for (Eigen::Index c = 0; c < k; ++c) {
                if constexpr (S == Store::Set) yi[c] = acc[c];
                if constexpr (S == Store::Residual) yi[c] = bs[i * k + c] - acc[c];
                if constexpr (S == Store::Add) yi[c] += acc[c];
            }
        }
    });
}

template <Store S>
void multiply_store(const RowSparse& A, const Block& x, Block& y, const Block* b = nullptr, int threads = 0) {
    if (x.rows() != A.cols()) throw InputError("AMG: block size mismatch");
    if (x.cols() == 3)
        multiply_k<3, S>(A, x, y, b, threads);
    else if (x.cols() == 1)
        multiply_k<1, S>(A, x, y, b, threads);  // the conformal factor's CG, the power iteration
    else
        multiply_k<0, S>(A, x, y, b, threads);
}

void multiply(const RowSparse& A, const Block& x, Block& y, int threads) {
    multiply_store<Store::Set>(A, x, y, nullptr, threads);
}

// Gauss-Seidel rows [begin, end) of one sweep on A x = b, in increasing (forward) or decreasing order.
template <int K>
void gauss_seidel_rows(const RowSparse& A, const Eigen::VectorXd& inv_diag, const Block& b, Block& x,
                       bool forward, Eigen::Index begin, Eigen::Index end) {
    const Eigen::Index k = K > 0 ? K : x.cols();
    const auto* outer = A.outerIndexPtr();
    const auto* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
    double* xs = x.data();
    const double* bs = b.data();
    double small[K > 0 ? K : 8];
    std::vector<double> big(K > 0 || k <= 8 ? 0 : static_cast<size_t>(k));
    double* acc = K > 0 || k <= 8 ? small : big.data();
    for (Eigen::Index t = begin; t < end; ++t) {
        const Eigen::Index i = forward ? t : end - 1 - (t - begin);
        for (Eigen::Index c = 0; c < k; ++c) acc[c] = bs[i * k + c];
        for (auto p = outer[i]; p < outer[i + 1]; ++p) {
            const double a = val[p];
            const double* xj = xs + static_cast<Eigen::Index>(inner[p]) * k;
            for (Eigen::Index c = 0; c < k; ++c) acc[c] -= a * xj[c];
        }
        const double d = inv_diag(i);
        for (Eigen::Index c = 0; c < k; ++c) xs[i * k + c] += acc[c] * d;
    }
}

// Colours the row chunks of a level that is large enough to share, so that no two chunks of one
// colour couple (no a_ij != 0 with i and j in two chunks of the same colour): greedily, chunks in
// index order, each taking the smallest colour none of its coupled chunks has. Returns the chunks
// sorted by colour (by index within a colour) and where each colour starts; empty for a level
// below kParallelNonZeros entries or when every chunk needs its own colour (nothing to share).
void colour_chunks(const RowSparse& A, std::vector<int>* order, std::vector<int>* start) {
    order->clear();
    start->clear();
    const Eigen::Index n = A.rows();
    if (A.nonZeros() < kParallelNonZeros) return;
    const int chunks = static_cast<int>((n + kChunkRows - 1) / kChunkRows);
    std::vector<std::vector<int>> coupled(static_cast<size_t>(chunks));
    for (int c = 0; c < chunks; ++c) {
        std::vector<int>& list = coupled[static_cast<size_t>(c)];
        const Eigen::Index begin = static_cast<Eigen::Index>(c) * kChunkRows;
        const Eigen::Index end = std::min(n, begin + kChunkRows);
        for (Eigen::Index i = begin; i < end; ++i)
            for (RowSparse::InnerIterator it(A, i); it; ++it) {
                const int d = static_cast<int>(it.col() / kChunkRows);
                if (d != c) list.push_back(d);
            }
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    std::vector<int> colour(static_cast<size_t>(chunks), -1);
    int colours = 0;
    for (int c = 0; c < chunks; ++c) {
        std::vector<char> taken(static_cast<size_t>(colours) + 1, 0);
        for (const int d : coupled[static_cast<size_t>(c)])
            if (colour[static_cast<size_t>(d)] >= 0)
                taken[static_cast<size_t>(colour[static_cast<size_t>(d)])] = 1;
        int q = 0;
        while (taken[static_cast<size_t>(q)]) ++q;
        colour[static_cast<size_t>(c)] = q;
        colours = std::max(colours, q + 1);
    }
    if (colours >= chunks) return;
    for (int q = 0; q < colours; ++q) {
        start->push_back(static_cast<int>(order->size()));
        for (int c = 0; c < chunks; ++c)
            if (colour[static_cast<size_t>(c)] == q) order->push_back(c);
    }
    start->push_back(static_cast<int>(order->size()));
}

// One Gauss-Seidel sweep on A x = b. Rows in increasing (forward) or decreasing order; on a level
// with coloured chunks, the chunks of one colour after another (forward: colours and rows
// increasing; backward: the exact reverse, so a forward and a backward sweep stay a symmetric
// smoother), the chunks of one colour on every hardware thread. Chunks of one colour do not
// couple, so this is Gauss-Seidel in a fixed order of the rows: the same result on any number of
// threads, and every row update still lowers the energy.
template <int K>
void gauss_seidel_k(const RowSparse& A, const Eigen::VectorXd& inv_diag, const std::vector<int>& order,
                    const std::vector<int>& start, const Block& b, Block& x, bool forward, int threads) {
    const Eigen::Index n = A.rows();
    if (order.empty()) {
        gauss_seidel_rows<K>(A, inv_diag, b, x, forward, 0, n);
        return;
    }
    const int colours = static_cast<int>(start.size()) - 1;
    ParallelOptions o;
    o.threads = threads;
    for (int s = 0; s < colours; ++s) {
        const int q = forward ? s : colours - 1 - s;
        const int first = start[static_cast<size_t>(q)], count = start[static_cast<size_t>(q) + 1] - first;
        parallel_for(
            count,
            [&](std::ptrdiff_t t, int) {
                const int c = order[static_cast<size_t>(first + (forward ? t : count - 1 - t))];
                const Eigen::Index begin = static_cast<Eigen::Index>(c) * kChunkRows;
                gauss_seidel_rows<K>(A, inv_diag, b, x, forward, begin, std::min(n, begin + kChunkRows));
            },
            o);
    }
}

void gauss_seidel(const RowSparse& A, const Eigen::VectorXd& inv_diag, const std::vector<int>& order,
                  const std::vector<int>& start, const Block& b, Block& x, bool forward, int threads) {
    if (x.cols() == 3)
        gauss_seidel_k<3>(A, inv_diag, order, start, b, x, forward, threads);
    else if (x.cols() == 1)
        gauss_seidel_k<1>(A, inv_diag, order, start, b, x, forward, threads);
    else
        gauss_seidel_k<0>(A, inv_diag, order, start, b, x, forward, threads);
}

// Sorts the columns within every row of a compressed matrix written by hand, as
// setFromTriplets() would have (Eigen's sparse products need not sort them).
void sort_rows(RowSparse& M) {
    auto* outer = M.outerIndexPtr();
    auto* inner = M.innerIndexPtr();
    double* val = M.valuePtr();
    std::vector<std::pair<int, double>> row;
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
        if (std::is_sorted(inner + outer[i], inner + outer[i + 1])) continue;
        row.clear();
        for (auto p = outer[i]; p < outer[i + 1]; ++p) row.emplace_back(inner[p], val[p]);
        std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (size_t r = 0; r < row.size(); ++r) {
            inner[outer[i] + static_cast<Eigen::Index>(r)] = row[r].first;
            val[outer[i] + static_cast<Eigen::Index>(r)] = row[r].second;
        }
    }
}

// A rows x cols matrix written row by row straight into compressed storage (no triplet list: 16
// bytes an entry): row_size(i) counts the entries of row i, then emit_row(i, put) calls
// put(column, value) for each of them, in any order (the rows are sorted afterwards). `nonzeros`
// (an estimate of the entries) decides as for the products whether the rows are shared out in
// chunks of kChunkRows; each row is counted and written by one chunk alone, so the matrix does
// not depend on the threads.
template <class RowSize, class EmitRow>
RowSparse compressed_rows(Eigen::Index rows, Eigen::Index cols, Eigen::Index nonzeros, int threads,
                          RowSize row_size, EmitRow emit_row) {
    RowSparse M(rows, cols);
    std::vector<Eigen::Index> count(static_cast<size_t>(rows) + 1, 0);
    for_row_chunks(rows, nonzeros, threads, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index i = begin; i < end; ++i) count[static_cast<size_t>(i) + 1] = row_size(i);
    });
    for (Eigen::Index i = 0; i < rows; ++i)
        count[static_cast<size_t>(i) + 1] += count[static_cast<size_t>(i)];
    M.resizeNonZeros(count.back());
    auto* outer = M.outerIndexPtr();
    auto* inner = M.innerIndexPtr();
    double* val = M.valuePtr();
    for (Eigen::Index i = 0; i <= rows; ++i) outer[i] = static_cast<int>(count[static_cast<size_t>(i)]);
    std::atomic<bool> miscounted{false};
    for_row_chunks(rows, nonzeros, threads, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index i = begin; i < end; ++i) {
            Eigen::Index q = outer[i];
            const Eigen::Index last = outer[i + 1];
            const auto put = [&](Eigen::Index j, double v) {
                if (q < last) {
                    inner[q] = static_cast<int>(j);
                    val[q] = v;
                }
                ++q;
            };
            emit_row(i, put);
            if (q != last) miscounted = true;
        }
    });
    if (miscounted)
        throw std::logic_error("compressed_rows: a row emitted another number of entries than counted");
    sort_rows(M);
    return M;
}

// C = A B, row by row: row i accumulates b_kj a_ik over row i's entries k in stored order (the
// first term assigned, the next ones added), its columns sorted (or, with `sorted` false, in the
// order they were first touched): what Eigen's product of two row-major matrices computes, to the
// bit, with every touched entry kept. Rows in chunks of
// kChunkRows, on every thread when A and B hold 1M non-zeros or more (each chunk's rows are
// written by that chunk alone: the same result on any number of threads).
RowSparse sparse_product(const RowSparse& A, const RowSparse& B, int threads, bool sorted = true) {
    if (A.cols() != B.rows()) throw std::logic_error("sparse_product: inner sizes differ");
    const Eigen::Index n = A.rows(), m = B.cols();
    const Eigen::Index chunks = (n + kChunkRows - 1) / kChunkRows;
    ParallelOptions o;
    o.threads = A.nonZeros() + B.nonZeros() >= kParallelNonZeros ? threads : 1;
    const int workers = parallel_workers(chunks, o);
    struct Accumulator {
        std::vector<double> value;
        std::vector<Eigen::Index> stamp;  // the row + 1 that last touched a column
        std::vector<int> touched;
    };
    std::vector<Accumulator> acc(static_cast<size_t>(workers));
    struct Part {
        std::vector<int> count, col;
        std::vector<double> val;
    };
    std::vector<Part> parts(static_cast<size_t>(chunks));
    const auto* ao = A.outerIndexPtr();
    const auto* ai = A.innerIndexPtr();
    const double* av = A.valuePtr();
    const auto* bo = B.outerIndexPtr();
    const auto* bi = B.innerIndexPtr();
    const double* bv = B.valuePtr();
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c, int worker) {
            Accumulator& w = acc[static_cast<size_t>(worker)];
            if (w.value.empty()) {
                w.value.resize(static_cast<size_t>(m));
                w.stamp.assign(static_cast<size_t>(m), 0);
            }
            Part& part = parts[static_cast<size_t>(c)];
            const Eigen::Index begin = static_cast<Eigen::Index>(c) * kChunkRows,
                               end = std::min(n, begin + kChunkRows);
            part.count.resize(static_cast<size_t>(end - begin));
            for (Eigen::Index i = begin; i < end; ++i) {
                w.touched.clear();
                for (auto p = ao[i]; p < ao[i + 1]; ++p) {
                    const double y = av[p];
                    const Eigen::Index k = ai[p];
                    for (auto q = bo[k]; q < bo[k + 1]; ++q) {
                        const int j = bi[q];
                        const size_t js = static_cast<size_t>(j);
                        if (w.stamp[js] != i + 1) {
                            w.stamp[js] = i + 1;
                            w.value[js] = bv[q] * y;
                            w.touched.push_back(j);
                        } else {
                            w.value[js] += bv[q] * y;
                        }
                    }
                }
                if (sorted) std::sort(w.touched.begin(), w.touched.end());
                part.count[static_cast<size_t>(i - begin)] = static_cast<int>(w.touched.size());
                for (const int j : w.touched) {
                    part.col.push_back(j);
                    part.val.push_back(w.value[static_cast<size_t>(j)]);
                }
            }
        },
        o);
    acc.clear();
    RowSparse C(n, m);
    std::vector<Eigen::Index> first(static_cast<size_t>(chunks) + 1, 0);
    for (Eigen::Index c = 0; c < chunks; ++c)
        first[static_cast<size_t>(c) + 1] =
            first[static_cast<size_t>(c)] +
            static_cast<Eigen::Index>(parts[static_cast<size_t>(c)].col.size());
    C.resizeNonZeros(first.back());
    auto* co = C.outerIndexPtr();
    auto* ci = C.innerIndexPtr();
    double* cv = C.valuePtr();
    co[0] = 0;
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c, int) {
            Part& part = parts[static_cast<size_t>(c)];
            const Eigen::Index begin = static_cast<Eigen::Index>(c) * kChunkRows;
            Eigen::Index q = first[static_cast<size_t>(c)];
            for (size_t r = 0; r < part.count.size(); ++r) {
                q += part.count[r];
                co[begin + static_cast<Eigen::Index>(r) + 1] = static_cast<int>(q);
            }
            std::copy(part.col.begin(), part.col.end(), ci + first[static_cast<size_t>(c)]);
            std::copy(part.val.begin(), part.val.end(), cv + first[static_cast<size_t>(c)]);
            std::vector<int>().swap(part.count);  // each chunk's buffers go as soon as copied
            std::vector<int>().swap(part.col);
            std::vector<double>().swap(part.val);
        },
        o);
    return C;
}

// The filtered matrix of smoothed aggregation: the diagonal and the strong off-diagonal entries
// (|a_ij| >= theta sqrt(a_ii a_jj)); weak entries are added to the diagonal, so row sums (and with
// them the constant near-null vector of a Laplacian) are kept - except in a row with no strong
// entry at all (a vertex whose neighbours all have far larger diagonals: an irregular mesh's
// short edges around it), which keeps a_ii, since its row sum may be 0. Its off-diagonal pattern is the
// strength graph of the aggregation; smoothing the prolongator with it instead of A keeps weak,
// long-range couplings (SMACOF's feature-point clique) from making P and the coarse levels dense.
RowSparse filtered_matrix(const RowSparse& A, const Eigen::VectorXd& diag, double theta,
                          std::vector<int>* weak_count, int threads) {
    // Written row by row straight into compressed storage (no triplet list: 16 bytes per entry).
    const Eigen::Index n = A.rows();
    const auto* outer = A.outerIndexPtr();
    const auto* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
    weak_count->assign(static_cast<size_t>(n), 0);
    const auto strong = [&](Eigen::Index i, Eigen::Index j, double a) {
        return std::abs(a) >= theta * std::sqrt(diag(i) * diag(j));
    };
    return compressed_rows(
        n, n, A.nonZeros(), threads,
        [&](Eigen::Index i) {
            Eigen::Index count = 1;  // the diagonal
            for (auto p = outer[i]; p < outer[i + 1]; ++p)
                if (inner[p] != i && strong(i, inner[p], val[p])) ++count;
            return count;
        },
        [&](Eigen::Index i, const auto& put) {
            double d = 0;
            bool any_strong = false;
            for (auto p = outer[i]; p < outer[i + 1]; ++p) {
                const Eigen::Index j = inner[p];
                if (j == i)
                    d += val[p];
                else if (!strong(i, j, val[p])) {
                    d += val[p];
                    ++(*weak_count)[static_cast<size_t>(i)];
                } else {
                    any_strong = true;
                }
            }
            // A row with no strong neighbour keeps its own diagonal: lumped, a graph Laplacian's
            // row would sum to 0 (or, by rounding, just below), which no Jacobi step can divide by.
            if (!any_strong) d = diag(i);
            bool diagonal_written = false;
            for (auto p = outer[i]; p < outer[i + 1]; ++p) {
                const Eigen::Index j = inner[p];
                if (j == i || !strong(i, j, val[p])) continue;
                if (!diagonal_written && j > i) {
                    put(i, d);
                    diagonal_written = true;
                }
                put(j, val[p]);
            }
            if (!diagonal_written) put(i, d);
        });
}

// Aggregates of the strength graph (the off-diagonal pattern of the filtered matrix F, with
// strengths |f_ij|; graph.h). Returns the aggregate of every row and sets *count.
std::vector<int> aggregate(const RowSparse& F, int* count) {
    const int n = static_cast<int>(F.rows());
    const auto* outer = F.outerIndexPtr();
    const auto* inner = F.innerIndexPtr();
    const double* val = F.valuePtr();
    WeightedAdjacency strong;
    strong.offsets.assign(static_cast<size_t>(n) + 1, 0);
    strong.neighbors.reserve(static_cast<size_t>(F.nonZeros()));
    strong.strengths.reserve(static_cast<size_t>(F.nonZeros()));
    for (int i = 0; i < n; ++i) {
        for (auto p = outer[i]; p < outer[i + 1]; ++p) {
            if (inner[p] == i) continue;
            strong.neighbors.push_back(inner[p]);
            strong.strengths.push_back(std::abs(val[p]));
        }
        strong.offsets[static_cast<size_t>(i) + 1] = static_cast<int>(strong.neighbors.size());
    }
    return aggregate_vertices(strong, count);
}

// The smoothed prolongator of aggregation `agg` (nc aggregates), P = P_t - omega D^-1 F P_t, where
// row i of the tentative P_t is e_agg(i) and D^-1 = inv_diag; rows for which keep_tentative(i) is
// true keep P_t's row, and entries that come out exactly 0 are left out. Row i of D^-1 F P_t sums,
// per aggregate, inv_diag(i) f_ik over row i's entries k in stored order (ColumnEntries, a row's
// entries summed as sparse_columns.h sums a column's) and P's entry is (1 if the aggregate is i's
// own, else 0) minus omega times that sum: what Eigen's sparse product and difference of D^-1 F,
// P_t and omega give, to the bit, without forming them. (F's diagonal puts i's own aggregate in
// every row.)
template <class KeepTentative>
RowSparse smoothed_prolongator(const RowSparse& F, const Eigen::VectorXd& inv_diag,
                               const std::vector<int>& agg, int nc, double omega,
                               const KeepTentative& keep_tentative, int threads) {
    const auto* fo = F.outerIndexPtr();
    const auto* fi = F.innerIndexPtr();
    const double* fv = F.valuePtr();
    thread_local ColumnEntries sums;
    // put(aggregate, entry) for row i's non-zero entries of P.
    const auto row = [&](Eigen::Index i, const auto& put) {
        const int own = agg[static_cast<size_t>(i)];
        if (keep_tentative(i)) {
            put(own, 1.0);
            return;
        }
        sums.clear();
        for (auto p = fo[i]; p < fo[i + 1]; ++p)
            sums.add(agg[static_cast<size_t>(fi[p])], inv_diag(i) * fv[p]);
        for (const auto& [a, sum] : sums.sorted()) {
            const double value = (a == own ? 1.0 : 0.0) - omega * sum;
            if (value != 0) put(a, value);
        }
    };
    return compressed_rows(
        F.rows(), nc, F.nonZeros(), threads,
        [&](Eigen::Index i) {
            Eigen::Index count = 0;
            row(i, [&count](int, double) { ++count; });
            return count;
        },
        row);
}

// Largest eigenvalue of D^-1 A by power iteration (fixed seed), with a 10% margin.
double spectral_radius_estimate(const RowSparse& A, const Eigen::VectorXd& inv_diag, int threads) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u(-1, 1);
    Block x(A.rows(), 1), y;
    for (Eigen::Index i = 0; i < x.rows(); ++i) x(i, 0) = u(rng);
    double lambda = 1;
    for (int it = 0; it < 15; ++it) {
        const double nx = x.norm();
        if (!(nx > 0)) break;
        // Per entry (the same values as Eigen's x /= nx and y *= D^-1), in row chunks shared like
        // the product's.
        double* xs = x.data();
        for_row_chunks(A.rows(), A.nonZeros(), threads, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index i = begin; i < end; ++i) xs[i] /= nx;
        });
        multiply(A, x, y, threads);
        double* ys = y.data();
        for_row_chunks(A.rows(), A.nonZeros(), threads, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index i = begin; i < end; ++i) ys[i] *= inv_diag(i);
        });
        lambda = y.norm();
        x.swap(y);
    }
    return 1.1 * lambda;
}

}  // namespace

const char* to_string(LinearSolver s) {
    switch (s) {
        case LinearSolver::Direct:
            return "direct";
        case LinearSolver::Multigrid:
            return "multigrid";
        case LinearSolver::Auto:
            break;
    }
    return "auto";
}

std::vector<std::string> linear_solver_names() {
    return {to_string(LinearSolver::Auto), to_string(LinearSolver::Direct),
            to_string(LinearSolver::Multigrid)};
}

bool use_multigrid(LinearSolver s, long long unknowns, long long threshold) {
    if (unknowns <= AmgOptions{}.coarse_size) return false;
    return s == LinearSolver::Multigrid || (s == LinearSolver::Auto && unknowns >= threshold);
}

AmgPreconditioner::AmgPreconditioner(const Eigen::SparseMatrix<double>& A0, const AmgOptions& options) {
    if (A0.rows() != A0.cols() || A0.rows() < 1)
        throw InputError("AMG: the matrix must be square and non-empty");
    if (options.smoothing_sweeps < 1 || options.max_levels < 1)
        throw InputError("AMG: smoothing_sweeps and max_levels must be at least 1 (given " +
                         std::to_string(options.smoothing_sweeps) + " and " +
                         std::to_string(options.max_levels) + ")");
    sweeps_ = options.smoothing_sweeps;
    threads_ = options.threads;
    RowSparse A = A0;
    A.makeCompressed();
    // Eigen 3.4's sparse matrices have no move operations (std::move copies them): the levels are
    // built in place (no reallocation of levels_) and matrices handed over with swap().
    levels_.reserve(static_cast<size_t>(options.max_levels));
    while (true) {
        levels_.emplace_back();
        Level& L = levels_.back();
        L.A.swap(A);
        const Eigen::VectorXd diag = L.A.diagonal();
        if (!(diag.array() > 0).all() || !diag.allFinite())
            throw NumericalError("AMG: the matrix has a non-positive or non-finite diagonal entry");
        L.inv_diag = diag.cwiseInverse();
        colour_chunks(L.A, &L.chunk_order, &L.colour_start);
        const Eigen::Index n = L.A.rows();
        if (n <= options.coarse_size || static_cast<int>(levels_.size()) >= options.max_levels) break;
        std::vector<int> weak;
        // Temporaries are scoped so that they go as soon as they are used (peak memory at 1M rows).
        RowSparse P;
        int nc = 0;
        std::vector<int> agg;
        {
            RowSparse F = filtered_matrix(L.A, diag, options.strength, &weak, options.threads);
            agg = aggregate(F, &nc);
            if (nc > 0.6 * static_cast<double>(n) || nc < 1)
                break;  // poor coarsening: a direct solve from here
            // Smoothed prolongator P = (I - omega D_F^-1 F) P_tent, omega = 4 / (3 rho(D_F^-1 F)).
            const Eigen::VectorXd inv_fdiag = F.diagonal().cwiseInverse();
            if (!inv_fdiag.allFinite() || !(inv_fdiag.array() > 0).all())
                throw NumericalError("AMG: the filtered matrix has a non-positive diagonal entry");
            const double omega = 4.0 / (3.0 * spectral_radius_estimate(F, inv_fdiag, options.threads));
            // Rows with many weak couplings (a feature point of SMACOF's clique) keep their tentative
            // row: the clique then couples only the aggregates holding its points, not every
            // aggregate around them, and the coarse levels stay sparse.
            const auto keep_tentative = [&](Eigen::Index i) {
                return weak[static_cast<size_t>(i)] > kManyWeakCouplings;
            };
            P = smoothed_prolongator(F, inv_fdiag, agg, nc, omega, keep_tentative, options.threads);
        }
        RowSparse R = P.transpose();
        {
            RowSparse Ac;
            {
                // A P's rows in the order their columns were first touched: only the product
                // below reads it, and a column's value there sums over R's row in R's order
                // whatever the order of A P's row, so its bits are the same.
                const RowSparse AP = sparse_product(L.A, P, options.threads, false);
                Ac = sparse_product(R, AP, options.threads);
            }
            const RowSparse AcT = Ac.transpose();
            A = 0.5 * (Ac + AcT);  // symmetric up to rounding; make it exactly so
        }
        A.prune(0.0);
        A.makeCompressed();
        if (A.nonZeros() > 2 * L.A.nonZeros()) break;  // the coarse operator fills in: stop coarsening
        L.P.swap(P);
        L.R.swap(R);
    }
    const Eigen::SparseMatrix<double> coarsest = levels_.back().A;
    if (!coarse_.compute(coarsest)) {
        std::ostringstream m;
        m << "AMG: the Cholesky factorisation of the coarsest level (" << coarsest.rows() << " rows) failed";
        throw NumericalError(m.str());
    }
}

void AmgPreconditioner::vcycle(int l, const Block& b, Block& x, bool zero_guess, Workspace& work) const {
    const Level& L = levels_[static_cast<size_t>(l)];
    if (l + 1 == static_cast<int>(levels_.size())) {
        const Eigen::MatrixXd sol = coarse_.solve(Eigen::MatrixXd(b));
        if (!coarse_.ok()) throw NumericalError("AMG: the coarsest-level solve failed");
        x = sol;
        return;
    }
    const size_t nl = levels_.size();
    if (work.residual.size() != nl) {
        work.residual.resize(nl);
        work.rhs.resize(nl);
        work.sol.resize(nl);
    }
    if (zero_guess) x.setZero(b.rows(), b.cols());
    // Pre-smoothing (forward), the coarse correction, post-smoothing (backward): symmetric.
    // (Each level stores P and R of the transfer to the next coarser level.)
    for (int s = 0; s < sweeps_; ++s)
        gauss_seidel(L.A, L.inv_diag, L.chunk_order, L.colour_start, b, x, true, threads_);
    Block& r = work.residual[static_cast<size_t>(l)];
    multiply_store<Store::Residual>(L.A, x, r, &b, threads_);  // r = b - A x
    Block& bc = work.rhs[static_cast<size_t>(l)];
    Block& xc = work.sol[static_cast<size_t>(l)];
    multiply(L.R, r, bc, threads_);
    vcycle(l + 1, bc, xc, true, work);
    multiply_store<Store::Add>(L.P, xc, x, nullptr, threads_);  // x += P xc
    for (int s = 0; s < sweeps_; ++s)
        gauss_seidel(L.A, L.inv_diag, L.chunk_order, L.colour_start, b, x, false, threads_);
}

void AmgPreconditioner::apply(const Block& R, Block& Z) const {
    if (levels_.empty()) throw NumericalError("AMG: apply() before set-up");
    Workspace work;
    vcycle(0, R, Z, true, work);
}

void AmgPreconditioner::cycle(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, int cycles) const {
    Workspace work;
    cycle(B, Eigen::Ref<Eigen::MatrixXd>(X), cycles, work);
}

void AmgPreconditioner::cycle(const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::Ref<Eigen::MatrixXd> X,
                              int cycles, Workspace& work) const {
    const Eigen::Index n = rows();
    if (B.rows() != n || X.rows() != n || X.cols() != B.cols())
        throw InputError("AMG: right-hand side and guess must have the matrix's number of rows");
    // The copies between the caller's column-major storage and the cycle's rows, in row chunks
    // shared like the sweeps (copies: the same values on any number of threads).
    const Eigen::Index k = B.cols();
    work.b.resize(n, k);
    work.x.resize(n, k);
    const Eigen::Index nonzeros = levels_[0].A.nonZeros();
    for_row_chunks(n, nonzeros, threads_, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index i = begin; i < end; ++i)
            for (Eigen::Index c = 0; c < k; ++c) {
                work.b(i, c) = B(i, c);
                work.x(i, c) = X(i, c);
            }
    });
    for (int c = 0; c < cycles; ++c) vcycle(0, work.b, work.x, false, work);
    for_row_chunks(n, nonzeros, threads_, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index c = 0; c < k; ++c)
            for (Eigen::Index i = begin; i < end; ++i) X(i, c) = work.x(i, c);
    });
}

PcgReport AmgPreconditioner::pcg(const Eigen::MatrixXd& B, Eigen::MatrixXd& X0, double tolerance,
                                 int max_iterations, int min_iterations) const {
    const Level& L = levels_.at(0);
    const Eigen::Index n = L.A.rows(), k = B.cols();
    if (B.rows() != n || X0.rows() != n || X0.cols() != k)
        throw InputError("AMG: right-hand side and guess must have the matrix's number of rows");
    Block x = X0, b = B, r, z, p, q;
    Workspace work;  // the V-cycle's vectors, allocated once for all CG steps
    multiply(L.A, x, q, threads_);
    r = b - q;
    const Eigen::ArrayXd r0 = r.colwise().norm().transpose();
    PcgReport rep;
    if ((r0 == 0).all()) {
        rep.converged = true;
        return rep;
    }
    vcycle(0, r, z, true, work);
    p = z;
    Eigen::ArrayXd rz = (r.array() * z.array()).colwise().sum().transpose();
    for (int it = 1; it <= max_iterations; ++it) {
        multiply(L.A, p, q, threads_);
        const Eigen::ArrayXd pq = (p.array() * q.array()).colwise().sum().transpose();
        Eigen::ArrayXd alpha(k);
        for (Eigen::Index c = 0; c < k; ++c) alpha(c) = (pq(c) > 0 && rz(c) > 0) ? rz(c) / pq(c) : 0.0;
        // x += p alpha, r -= q alpha (per entry, in row chunks shared like the sweeps)
        for_row_chunks(n, L.A.nonZeros(), threads_, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index i = begin; i < end; ++i)
                for (Eigen::Index c = 0; c < k; ++c) {
                    x(i, c) += p(i, c) * alpha(c);
                    r(i, c) -= q(i, c) * alpha(c);
                }
        });
        rep.iterations = it;
        double rel = 0;
        const Eigen::ArrayXd rn = r.colwise().norm().transpose();
        for (Eigen::Index c = 0; c < k; ++c)
            if (r0(c) > 0) rel = std::max(rel, rn(c) / r0(c));
        rep.relative_residual = rel;
        if (!std::isfinite(rel)) throw NumericalError("AMG-preconditioned CG produced non-finite values");
        if (rel <= tolerance && it >= min_iterations) {
            rep.converged = true;
            break;
        }
        vcycle(0, r, z, true, work);
        const Eigen::ArrayXd rz_new = (r.array() * z.array()).colwise().sum().transpose();
        Eigen::ArrayXd beta(k);
        for (Eigen::Index c = 0; c < k; ++c) beta(c) = rz(c) > 0 ? rz_new(c) / rz(c) : 0.0;
        for_row_chunks(n, L.A.nonZeros(), threads_, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index i = begin; i < end; ++i)
                for (Eigen::Index c = 0; c < k; ++c) p(i, c) = z(i, c) + p(i, c) * beta(c);
        });
        rz = rz_new;
    }
    X0 = x;
    return rep;
}

double AmgPreconditioner::operator_complexity() const {
    if (levels_.empty()) return 0;
    double total = 0;
    for (const Level& L : levels_) total += static_cast<double>(L.A.nonZeros());
    return total / static_cast<double>(levels_[0].A.nonZeros());
}

}  // namespace canonform::numerics
