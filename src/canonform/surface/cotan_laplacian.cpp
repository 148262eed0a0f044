#include "canonform/surface/cotan_laplacian.h"

#include <Eigen/Geometry>

#include <vector>

namespace canonform {

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    const Eigen::Index n = V.rows();
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<size_t>(F.rows()) * 12);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
            // corner k is opposite the edge (i, j)
            const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3), k = F(f, c);
            const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
            const double w = 0.5 * a.dot(b) / a.cross(b).norm();  // cot of the angle at k, halved
            t.emplace_back(i, j, -w);
            t.emplace_back(j, i, -w);
            t.emplace_back(i, i, w);
            t.emplace_back(j, j, w);
        }
    }
    Eigen::SparseMatrix<double> L(n, n);
    L.setFromTriplets(t.begin(), t.end());
    return L;
}

}  // namespace canonform
