// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/cotan_laplacian.h"

#include <Eigen/Geometry>

#include <vector>

namespace canonform::surface {

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    const Eigen::Index n = V.rows();
    // Assembled in place, without a triplet list: a face adds at most two off-diagonal entries
    // and the diagonal to the column of each of its vertices, so 2 (faces at v) + 1 slots per
    // column suffice. (A triplet list of the 12 contributions per face took 16 bytes each, 384 MB
    // at 1M vertices, plus Eigen's transposed copy of it.) The contributions are added in the
    // same order as setFromTriplets() summed them, so the values are the same to the bit.
    Eigen::VectorXi capacity = Eigen::VectorXi::Ones(n);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        for (int c = 0; c < 3; ++c) capacity(F(f, c)) += 2;
    Eigen::SparseMatrix<double> L(n, n);
    L.reserve(capacity);
    capacity.resize(0);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
            // corner k is opposite the edge (i, j)
            const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3), k = F(f, c);
            const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
            const double w = 0.5 * a.dot(b) / a.cross(b).norm();  // cot of the angle at k, halved
            L.coeffRef(i, j) += -w;
            L.coeffRef(j, i) += -w;
            L.coeffRef(i, i) += w;
            L.coeffRef(j, j) += w;
        }
    }
    L.makeCompressed();
    return L;
}

}  // namespace canonform::surface
