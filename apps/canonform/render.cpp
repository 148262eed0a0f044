// SPDX-License-Identifier: GPL-3.0-or-later
#include "render.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace canonform::render {

Image::Image(int w, int h, Eigen::Vector3d background)
    : width(w),
      height(h),
      rgb(static_cast<size_t>(w) * h * 3),
      depth(static_cast<size_t>(w) * h, -std::numeric_limits<float>::infinity()) {
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k)
        for (int c = 0; c < 3; ++c)
            rgb[3 * k + c] = static_cast<std::uint8_t>(std::lround(255 * background(c)));
}

View fit_view(const Eigen::MatrixXd& V, int width, int height, int margin) {
    const Eigen::RowVector3d c = V.colwise().mean();
    const Eigen::MatrixXd X = V.rowwise() - c;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(X.transpose() * X);
    // eigenvalues ascending: columns 2 (largest) = up, 1 = right, 0 (smallest) = view direction
    View v;
    Eigen::Vector3d up = es.eigenvectors().col(2), right = es.eigenvectors().col(1);
    Eigen::Vector3d toward = right.cross(up);
    v.R.row(0) = right.transpose();
    v.R.row(1) = up.transpose();
    v.R.row(2) = toward.transpose();
    const Eigen::MatrixXd P = X * v.R.transpose();
    const Eigen::Vector2d lo = P.leftCols(2).colwise().minCoeff(), hi = P.leftCols(2).colwise().maxCoeff();
    const double sx = (width - 2.0 * margin) / std::max(hi(0) - lo(0), 1e-12);
    const double sy = (height - 2.0 * margin) / std::max(hi(1) - lo(1), 1e-12);
    v.scale = std::min(sx, sy);
    const Eigen::Vector2d mid = 0.5 * (lo + hi);
    // pixel = offset + scale * (x, -y): the world origin of this view is the centroid c
    v.offset = Eigen::Vector2d(width / 2.0 - v.scale * mid(0), height / 2.0 + v.scale * mid(1));
    v.offset -= v.scale * Eigen::Vector2d((v.R.row(0) * c.transpose())(0), -(v.R.row(1) * c.transpose())(0));
    return v;
}

namespace {

Eigen::Vector3d project(const View& v, const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = v.R * p;
    return {v.offset(0) + v.scale * q(0), v.offset(1) - v.scale * q(1), q(2)};
}

}  // namespace

void draw_mesh(Image& img, const View& view, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::MatrixXd& C) {
    std::vector<Eigen::Vector3d> P(static_cast<size_t>(V.rows()));
    for (Eigen::Index k = 0; k < V.rows(); ++k)
        P[static_cast<size_t>(k)] = project(view, V.row(k).transpose());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d &a = P[static_cast<size_t>(F(f, 0))], &b = P[static_cast<size_t>(F(f, 1))],
                              &c = P[static_cast<size_t>(F(f, 2))];
        const Eigen::Vector3d e1 = (V.row(F(f, 1)) - V.row(F(f, 0))).transpose();
        const Eigen::Vector3d e2 = (V.row(F(f, 2)) - V.row(F(f, 0))).transpose();
        const Eigen::Vector3d n = e1.cross(e2);
        const double nn = n.norm();
        if (!(nn > 0)) continue;
        const double shade = 0.25 + 0.75 * std::abs((view.R.row(2) * n)(0)) / nn;
        const double area = (b(0) - a(0)) * (c(1) - a(1)) - (b(1) - a(1)) * (c(0) - a(0));
        if (std::abs(area) < 1e-12) continue;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a(0), b(0), c(0)}))));
        const int x1 = std::min(img.width - 1, static_cast<int>(std::ceil(std::max({a(0), b(0), c(0)}))));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a(1), b(1), c(1)}))));
        const int y1 = std::min(img.height - 1, static_cast<int>(std::ceil(std::max({a(1), b(1), c(1)}))));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                const double w0 = ((b(0) - px) * (c(1) - py) - (b(1) - py) * (c(0) - px)) / area;
                const double w1 = ((c(0) - px) * (a(1) - py) - (c(1) - py) * (a(0) - px)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float z = static_cast<float>(w0 * a(2) + w1 * b(2) + w2 * c(2));
                const size_t k = static_cast<size_t>(y) * img.width + x;
                if (z <= img.depth[k]) continue;
                img.depth[k] = z;
                const Eigen::Vector3d col =
                    shade * (w0 * C.row(F(f, 0)) + w1 * C.row(F(f, 1)) + w2 * C.row(F(f, 2))).transpose();
                for (int ch = 0; ch < 3; ++ch)
                    img.rgb[3 * k + ch] =
                        static_cast<std::uint8_t>(std::clamp(std::lround(255 * col(ch)), 0L, 255L));
            }
        }
    }
}

void draw_points(Image& img, const View& view, const Eigen::MatrixXd& P, const Eigen::Vector3d& color,
                 int radius, double tolerance) {
    for (Eigen::Index k = 0; k < P.rows(); ++k) {
        const Eigen::Vector3d p = project(view, P.row(k).transpose());
        const int cx = static_cast<int>(p(0)), cy = static_cast<int>(p(1));
        bool visible = true;
        if (cx >= 0 && cy >= 0 && cx < img.width && cy < img.height)
            visible = p(2) >= img.depth[static_cast<size_t>(cy) * img.width + cx] - tolerance;
        for (int dy = -radius; dy <= radius; ++dy) {
            for (int dx = -radius; dx <= radius; ++dx) {
                const int r2 = dx * dx + dy * dy, x = cx + dx, y = cy + dy;
                if (r2 > radius * radius || x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
                const bool rim = r2 > (radius - 1) * (radius - 1);
                if (!visible && !rim) continue;
                const Eigen::Vector3d col = rim ? Eigen::Vector3d::Zero().eval() : color;
                const size_t i = 3 * (static_cast<size_t>(y) * img.width + x);
                for (int ch = 0; ch < 3; ++ch)
                    img.rgb[i + ch] = static_cast<std::uint8_t>(std::lround(255 * col(ch)));
            }
        }
    }
}

Eigen::Vector3d ramp(double t) {
    t = std::clamp(t, 0.0, 1.0);
    static const Eigen::Vector3d stops[5] = {
        {0.1, 0.2, 0.9}, {0.1, 0.8, 0.9}, {0.2, 0.8, 0.2}, {0.95, 0.9, 0.1}, {0.9, 0.15, 0.1}};
    const double s = t * 4;
    const int i = std::min(3, static_cast<int>(s));
    return stops[i] + (s - i) * (stops[i + 1] - stops[i]);
}

}  // namespace canonform::render
