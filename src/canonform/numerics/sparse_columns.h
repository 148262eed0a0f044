// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: a sparse matrix assembled column by column, each entry's terms summed in a given order.
//
// Why: the cotangent Laplacian (surface/cotan_laplacian.h) and SMACOF's V (smacof.h) add several
// terms to each entry, and the order of those additions fixes the entry's bits (coeffRef() or
// setFromTriplets(), term after term). Gathering each column's terms in that order and summing
// them there gives the same values, writes the compressed arrays directly (no triplet list, no
// search per term) and lets the columns be made on every thread.
#pragma once

#include "canonform/common/parallel.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <utility>
#include <vector>

namespace canonform::numerics {

/// The entries of one column being summed: add(row, x) adds x to the row's entry, which starts at
/// 0 as an entry coeffRef() creates does (0 + x), the terms of each row in call order.
class ColumnEntries {
public:
    void clear() { entries_.clear(); }
    void add(int row, double x) {
        for (auto& e : entries_)
            if (e.first == row) {
                e.second += x;
                return;
            }
        entries_.emplace_back(row, 0.0 + x);
    }
    /// The (row, value) entries by increasing row.
    const std::vector<std::pair<int, double>>& sorted() {
        std::sort(entries_.begin(), entries_.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        return entries_;
    }

private:
    std::vector<std::pair<int, double>> entries_;
};

/// The rows x cols compressed column-major matrix whose column c holds what column(c, entries)
/// adds to a cleared ColumnEntries. Columns in ranges, shared out as parallel_rows() shares rows
/// (the matrix does not depend on the threads). column() is called twice for each column, to count
/// and then to write, and must add the same terms both times.
template <class Column>
Eigen::SparseMatrix<double> assemble_columns(Eigen::Index rows, Eigen::Index cols, int threads,
                                             const Column& column) {
    std::vector<int> start(static_cast<size_t>(cols) + 1, 0);
    parallel_rows(cols, threads, [&](Eigen::Index begin, Eigen::Index end) {
        ColumnEntries entries;
        for (Eigen::Index c = begin; c < end; ++c) {
            entries.clear();
            column(c, entries);
            start[static_cast<size_t>(c) + 1] = static_cast<int>(entries.sorted().size());
        }
    });
    for (Eigen::Index c = 0; c < cols; ++c)
        start[static_cast<size_t>(c) + 1] += start[static_cast<size_t>(c)];
    Eigen::SparseMatrix<double> M(rows, cols);
    M.resizeNonZeros(start.back());
    std::copy(start.begin(), start.end(), M.outerIndexPtr());
    int* inner = M.innerIndexPtr();
    double* values = M.valuePtr();
    parallel_rows(cols, threads, [&](Eigen::Index begin, Eigen::Index end) {
        ColumnEntries entries;
        for (Eigen::Index c = begin; c < end; ++c) {
            entries.clear();
            column(c, entries);
            int q = start[static_cast<size_t>(c)];
            for (const auto& [row, value] : entries.sorted()) {
                inner[q] = row;
                values[q++] = value;
            }
        }
    });
    return M;
}

}  // namespace canonform::numerics
