// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/depth_render.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>

namespace canonform::views {

std::vector<std::uint8_t> DepthImage::gray() const {
    std::vector<std::uint8_t> g(depth.size());
    for (size_t i = 0; i < depth.size(); ++i) {
        const double v = std::round(255.0 * std::clamp(static_cast<double>(depth[i]), 0.0, 1.0));
        g[i] = static_cast<std::uint8_t>(v);
    }
    return g;
}

Eigen::Matrix3d camera_frame(const Eigen::Vector3d& direction) {
    const double n = direction.norm();
    if (!std::isfinite(n) || !(n > 0))
        throw InputError("render_depth: the view direction must be finite and non-zero");
    const Eigen::Vector3d d = direction / n;
    const Eigen::Vector3d a = d.cwiseAbs();
    const double m = a.minCoeff();
    int k = 0;
    while (a[k] > m + 1e-9) ++k;
    Eigen::Vector3d u = Eigen::Vector3d::Unit(k) - d[k] * d;
    u.normalize();
    const Eigen::Vector3d r = u.cross(d);
    Eigen::Matrix3d C;
    C.row(0) = r.transpose();
    C.row(1) = u.transpose();
    C.row(2) = d.transpose();
    return C;
}

namespace {

struct P2 {
    double x, y;
};

// One edge function of a triangle: twice the signed area of (a, b, p), evaluated with (a, b) in a
// canonical order so that the value for the reversed edge is the exact negation (neighbouring
// triangles then agree on which of them covers a pixel centre on their shared edge). The
// canonical order, the differences and the row's term are set up once per triangle and row; the
// value per pixel is the same expression in the same order as evaluating it whole.
struct EdgeFn {
    double sx, sy, dx, dy, negate;  // canonical start, t - s, -1 when (a, b) was swapped
    EdgeFn(const P2& a, const P2& b) {
        const bool swap = (b.x < a.x) || (b.x == a.x && b.y < a.y);
        const P2& s = swap ? b : a;
        const P2& t = swap ? a : b;
        sx = s.x;
        sy = s.y;
        dx = t.x - s.x;
        dy = t.y - s.y;
        negate = swap ? -1.0 : 1.0;
    }
    double row(double py) const { return dx * (py - sy); }
    double at(double row_term, double px) const { return negate * (row_term - dy * (px - sx)); }
};

}  // namespace

namespace {

void check_render_input(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int size) {
    if (size < 1 || size > 8192) throw InputError("render_depth: the image size must be in 1..8192");
    if (V.cols() != 3 || (F.size() > 0 && F.cols() != 3))
        throw InputError("render_depth: V must be #V x 3 and F #F x 3");
    if (!V.allFinite()) throw InputError("render_depth: the mesh has non-finite vertex coordinates");
    if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()))
        throw InputError("render_depth: a face index is out of range");
}

// A size x size image of background (0).
DepthImage blank_image(int size) {
    DepthImage img;
    img.size = size;
    img.depth.assign(static_cast<size_t>(size) * size, 0.0f);
    return img;
}

// Per-vertex projections of rasterize(), kept per thread from one view to the next.
struct Projection {
    std::vector<P2> q;
    std::vector<double> z;
    std::vector<int> cx, fx, cy, fy;
};

// The depth image seen along camera frame C into `front` (size x size, zero-filled); when `back`
// is given (also zero-filled), also the opposite view's image: at each covered pixel the largest
// 1 - depth, i.e. the farthest surface of this view, stored mirrored (column c at size - 1 - c: see
// render_depth_pair).
void rasterize(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Matrix3d& C, int size,
               float* front, float* back) {
    // Project: pixel coordinates (col, row as doubles; centres at integers) and depth; per vertex
    // also the first pixel column/row at or after it and the last at or before it (ceil and floor,
    // clamped to [-1, size] - enough, as triangles are clipped to [0, size - 1] - so a triangle's
    // pixel box is integer minima and maxima of its corners', the same box as ceil(min) and
    // floor(max) of the coordinates).
    const double inv_h = size / 2.0;
    const Eigen::Index nv = V.rows();
    thread_local Projection scratch;
    const size_t nvs = static_cast<size_t>(nv);
    scratch.q.resize(nvs);
    scratch.z.resize(nvs);
    scratch.cx.resize(nvs);
    scratch.fx.resize(nvs);
    scratch.cy.resize(nvs);
    scratch.fy.resize(nvs);
    std::vector<P2>& q = scratch.q;
    std::vector<double>& z = scratch.z;
    std::vector<int>&cx = scratch.cx, &fx = scratch.fx, &cy = scratch.cy, &fy = scratch.fy;
    const auto clamp_pixel = [size](double v) {
        return static_cast<int>(std::min(double(size), std::max(-1.0, v)));
    };
    for (Eigen::Index i = 0; i < nv; ++i) {
        const double x = C(0, 0) * V(i, 0) + C(0, 1) * V(i, 1) + C(0, 2) * V(i, 2);
        const double y = C(1, 0) * V(i, 0) + C(1, 1) * V(i, 1) + C(1, 2) * V(i, 2);
        const double w = C(2, 0) * V(i, 0) + C(2, 1) * V(i, 1) + C(2, 2) * V(i, 2);
        const size_t k = static_cast<size_t>(i);
        q[k] = {(x + 1.0) * inv_h - 0.5, (1.0 - y) * inv_h - 0.5};
        z[k] = 0.5 * (1.0 + w);
        cx[k] = clamp_pixel(std::ceil(q[k].x));
        fx[k] = clamp_pixel(std::floor(q[k].x));
        cy[k] = clamp_pixel(std::ceil(q[k].y));
        fy[k] = clamp_pixel(std::floor(q[k].y));
    }

    const int lim = size - 1;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const int ia = F(f, 0), ib = F(f, 1), ic = F(f, 2);
        const size_t a_ = static_cast<size_t>(ia), b_ = static_cast<size_t>(ib), c_ = static_cast<size_t>(ic);
        // The pixel centres the triangle's box holds (most triangles of a fine mesh hold none).
        const int c0 = std::max(0, std::min({cx[a_], cx[b_], cx[c_]}));
        const int c1 = std::min(lim, std::max({fx[a_], fx[b_], fx[c_]}));
        if (c0 > c1) continue;
        const int r0 = std::max(0, std::min({cy[a_], cy[b_], cy[c_]}));
        const int r1 = std::min(lim, std::max({fy[a_], fy[b_], fy[c_]}));
        if (r0 > r1) continue;
        const P2& a = q[a_];
        const P2& b = q[b_];
        const P2& c = q[c_];
        const double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (!(std::abs(area2) > 1e-12)) continue;
        // Orientation-independent: scale the edge functions by the sign of the area.
        const double sgn = area2 > 0 ? 1.0 : -1.0;
        const double inv_area = 1.0 / area2;
        const double za = z[a_], zb = z[b_], zc = z[c_];
        const EdgeFn ea(b, c), eb(c, a), ec(a, b);
        for (int row = r0; row <= r1; ++row) {
            const double py = row;
            const double ra = ea.row(py), rb = eb.row(py), rc = ec.row(py);
            float* line = front + static_cast<size_t>(row) * size;
            float* far_line =
                back ? back + static_cast<size_t>(row) * size + (size - 1) : nullptr;  // mirrored
            for (int col = c0; col <= c1; ++col) {
                const double px = col;
                const double wa = ea.at(ra, px);
                if (sgn * wa < 0) continue;
                const double wb = eb.at(rb, px);
                if (sgn * wb < 0) continue;
                const double wc = ec.at(rc, px);
                if (sgn * wc < 0) continue;
                double d = (wa * za + wb * zb + wc * zc) * inv_area;
                d = std::min(1.0, std::max(0.0, d));
                const float df = static_cast<float>(d);
                if (df > line[col]) line[col] = df;
                if (far_line) {
                    const float bf = static_cast<float>(1.0 - d);
                    if (bf > far_line[-col]) far_line[-col] = bf;
                }
            }
        }
    }
}

}  // namespace

DepthImage render_depth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& direction,
                        int size) {
    check_render_input(V, F, size);
    const Eigen::Matrix3d C = camera_frame(direction);
    DepthImage img = blank_image(size);
    if (F.rows() > 0) rasterize(V, F, C, size, img.depth.data(), nullptr);
    return img;
}

std::array<DepthImage, 2> render_depth_pair(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const Eigen::Vector3d& direction, int size) {
    check_render_input(V, F, size);
    const Eigen::Matrix3d C = camera_frame(direction);
    std::array<DepthImage, 2> img = {blank_image(size), blank_image(size)};
    // The opposite camera has the same up vector and the opposite right vector (camera_frame):
    // its column c is this view's column size - 1 - c.
    if (F.rows() > 0) rasterize(V, F, C, size, img[0].depth.data(), img[1].depth.data());
    return img;
}

DepthRenderer::DepthRenderer(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int size)
    : V_(V), F_(F), size_(size) {
    check_render_input(V, F, size);
}

void DepthRenderer::pair_into(const Eigen::Vector3d& direction, float* front, float* back) const {
    const Eigen::Matrix3d C = camera_frame(direction);
    const size_t n = static_cast<size_t>(size_) * static_cast<size_t>(size_);
    std::fill(front, front + n, 0.0f);
    std::fill(back, back + n, 0.0f);
    if (F_.rows() > 0) rasterize(V_, F_, C, size_, front, back);
}

}  // namespace canonform::views
