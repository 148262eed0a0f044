// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/surface/gaussian_curvature.h"

#include "canonform/common/errors.h"
#include "canonform/common/parallel.h"
#include "canonform/numerics/portable_math.h"
#include "canonform/surface/mesh_topology.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace canonform::surface {

Eigen::VectorXd gaussian_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                   const std::vector<bool>& known_boundary, int threads) {
    if (!known_boundary.empty() && static_cast<Eigen::Index>(known_boundary.size()) != V.rows())
        throw InputError("gaussian_curvature: the boundary flags do not have one entry per vertex");
    const auto boundary =
        known_boundary.empty() ? boundary_vertices(static_cast<int>(V.rows()), F) : known_boundary;
    Eigen::VectorXd K(V.rows());
    for (Eigen::Index v = 0; v < V.rows(); ++v) K(v) = boundary[static_cast<size_t>(v)] ? M_PI : 2 * M_PI;
    // The angles of a block of faces at a time (three per face, in order), then subtracted in the
    // same order as one by one: the same bits, with the arctangents four at a time. From
    // kShareRowsFrom faces a block's angles are computed in ranges of 16,384 faces on every thread
    // (below it, blocks of 512 faces on the calling thread alone: no pool for small work).
    const bool share = F.rows() >= kShareRowsFrom;
    const Eigen::Index range = share ? 16384 : 512, block = share ? 16 * range : range;
    std::vector<double> ys(static_cast<size_t>(3 * block)), xs(ys.size()), angles(ys.size());
    for (Eigen::Index first = 0; first < F.rows(); first += block) {
        const Eigen::Index last = std::min<Eigen::Index>(F.rows(), first + block);
        parallel_ranges(last - first, range, share, threads, [&](Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index f = first + begin; f < first + end; ++f)
                for (int c = 0; c < 3; ++c) {
                    const size_t m = static_cast<size_t>(3 * (f - first) + c);
                    const int k = F(f, c), i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
                    const Eigen::Vector3d a = V.row(i) - V.row(k), b = V.row(j) - V.row(k);
                    ys[m] = a.cross(b).norm();
                    xs[m] = a.dot(b);
                }
            // not libm: the same bits on every CPU
            numerics::portable_atan2(ys.data() + 3 * begin, xs.data() + 3 * begin, angles.data() + 3 * begin,
                                     static_cast<size_t>(3 * (end - begin)));
        });
        size_t m = 0;
        for (Eigen::Index f = first; f < last; ++f)
            for (int c = 0; c < 3; ++c, ++m) K(F(f, c)) -= angles[m];
    }
    return K;
}

}  // namespace canonform::surface
