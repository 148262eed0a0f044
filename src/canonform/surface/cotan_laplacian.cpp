// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/cotan_laplacian.h"

#include "canonform/common/parallel.h"
#include "canonform/numerics/sparse_columns.h"

#include <Eigen/Geometry>

#include <vector>

namespace canonform::surface {

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int threads) {
    const Eigen::Index n = V.rows(), m = F.rows();
    // The definition, face by face: corner c of face f (opposite the edge (i, j)) adds -w to
    // (i, j) and (j, i), then +w to (i, i) and (j, j), every entry starting from 0; w is half the
    // cotangent of the corner's angle. Built here column by column, each entry's terms added in
    // that order of faces and corners (so its value is the same to the bit), the columns in
    // parallel: first the weights of all corners, then each vertex's corners in order.
    std::vector<double> w(static_cast<size_t>(3 * m));
    parallel_rows(m, threads, [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index f = begin; f < end; ++f)
            for (int c = 0; c < 3; ++c) {
                const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3), k = F(f, c);
                const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
                w[static_cast<size_t>(3 * f + c)] = 0.5 * a.dot(b) / a.cross(b).norm();
            }
    });
    // The corners whose edge ends at v (corner 3 f + c), in order: a counting sort.
    std::vector<int> first(static_cast<size_t>(n) + 1, 0);
    for (Eigen::Index f = 0; f < m; ++f)
        for (int c = 0; c < 3; ++c) {
            const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
            ++first[static_cast<size_t>(i) + 1];
            if (j != i) ++first[static_cast<size_t>(j) + 1];
        }
    for (Eigen::Index v = 0; v < n; ++v) first[static_cast<size_t>(v) + 1] += first[static_cast<size_t>(v)];
    std::vector<int> corners(static_cast<size_t>(first.back()));
    {
        std::vector<int> next(first.begin(), first.end() - 1);
        for (Eigen::Index f = 0; f < m; ++f)
            for (int c = 0; c < 3; ++c) {
                const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
                const int corner = static_cast<int>(3 * f + c);
                corners[static_cast<size_t>(next[static_cast<size_t>(i)]++)] = corner;
                if (j != i) corners[static_cast<size_t>(next[static_cast<size_t>(j)]++)] = corner;
            }
    }
    // Column v: its terms in order ((i, j) gets -w where j = v, (j, i) where i = v, then (v, v)
    // +w for each of i and j that is v).
    return numerics::assemble_columns(n, n, threads, [&](Eigen::Index v, numerics::ColumnEntries& column) {
        for (int p = first[static_cast<size_t>(v)]; p < first[static_cast<size_t>(v) + 1]; ++p) {
            const int corner = corners[static_cast<size_t>(p)];
            const Eigen::Index f = corner / 3;
            const int c = corner % 3;
            const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
            const double x = w[static_cast<size_t>(corner)];
            if (j == v) column.add(i, -x);
            if (i == v) column.add(j, -x);
            if (i == v) column.add(i, x);
            if (j == v) column.add(j, x);
        }
    });
}

}  // namespace canonform::surface
