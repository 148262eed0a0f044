// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/depth_render.h"

#include "canonform/common/cpu_clones.h"
#include "canonform/common/vector4d.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

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
    // At one pixel (T = double) or at adjacent pixels of a row, one per lane (T a vector).
    template <class T>
    T at(T row_term, T px) const {
        return negate * (row_term - dy * (px - sx));
    }
};

}  // namespace

namespace {

void check_render_input(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int size) {
    if (size < 2 || size > 8192) throw InputError("render_depth: the image size must be in 2..8192");
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

// One vertex as rasterize() sees it: pixel coordinates, depth, and the first pixel column/row at
// or after it and the last at or before it; kept per thread from one view to the next.
struct Projected {
    P2 q;
    double z;
    int cx, fx, cy, fy;
};

typedef double v2d __attribute__((vector_size(16)));
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));
typedef long long v2l __attribute__((vector_size(16)));
typedef float v2f __attribute__((vector_size(8)));
typedef int v2i __attribute__((vector_size(8)));

inline v2d splat2(double x) {
    return v2d{x, x};
}

// Two adjacent floats p[0], p[1] raised to v where `covered`, each as `if (v > p) p = v`; the
// other lane writes back what it read.
inline void raise2(float* p, v2f v, v2i covered) {
    v2f old;
    std::memcpy(&old, p, sizeof old);
    const v2f raised = old < v ? v : old;
    const v2f out = covered ? raised : old;
    std::memcpy(p, &out, sizeof out);
}

// One triangle's depth at pixel centres, two adjacent pixels of a row at a time, with no branch
// per pixel (faces of a fine mesh cover a pixel or two, and which is unpredictable). Each lane
// evaluates the edge functions, the inside test and the interpolated, clamped depth in one fixed
// order of IEEE operations, so a pixel gets the same bits in either lane, on every CPU. Raising a
// pixel twice to the same value changes nothing, which lets a row's last pair overlap the one
// before it.
struct TriangleDepth {
    const EdgeFn &ea, &eb, &ec;
    double sgn, za, zb, zc, inv_area;
    int size;
    float *front, *back;

    // Pixels (row, col) and (row, col + 1), lanes where `keep` is set; `col + 1 < size`.
    void pair(int row, int col, v2l keep) const {
        const double py = row;
        const v2d px = v2d{double(col), double(col + 1)}, zero = splat2(0.0), one = splat2(1.0);
        const v2d wa = ea.at(splat2(ea.row(py)), px), wb = eb.at(splat2(eb.row(py)), px),
                  wc = ec.at(splat2(ec.row(py)), px);
        const v2d s2 = splat2(sgn);
        const v2l outside = (s2 * wa < zero) | (s2 * wb < zero) | (s2 * wc < zero);
        v2d d = (wa * splat2(za) + wb * splat2(zb) + wc * splat2(zc)) * splat2(inv_area);
        d = zero < d ? d : zero;  // std::max(0.0, d)
        d = d < one ? d : one;    // std::min(1.0, d)
        const v2i covered = __builtin_convertvector(~outside & keep, v2i);
        const size_t line = static_cast<size_t>(row) * static_cast<size_t>(size);
        raise2(front + line + static_cast<size_t>(col), __builtin_convertvector(d, v2f), covered);
        if (back) {  // mirrored: columns size - 2 - col and size - 1 - col, lanes swapped
            const v2f far = __builtin_convertvector(one - d, v2f);
            raise2(back + line + static_cast<size_t>(size - 2 - col), v2f{far[1], far[0]},
                   v2i{covered[1], covered[0]});
        }
    }

    // Four pixels' depths (clamped to [0, 1]) and the lanes the face leaves out, from each edge's
    // row term and the pixels' columns, lane by lane: pair()'s operations in its order.
    void depth4(const v4d& ta, const v4d& tb, const v4d& tc, const v4d& px, v4d& d, v4l& outside) const {
        const v4d zero = v4d{} + 0.0, one = v4d{} + 1.0;
        const v4d wa = ea.at(ta, px), wb = eb.at(tb, px), wc = ec.at(tc, px);
        const v4d s4 = v4d{} + sgn;
        outside = (s4 * wa < zero) | (s4 * wb < zero) | (s4 * wc < zero);
        d = (wa * za + wb * zb + wc * zc) * inv_area;
        d = zero < d ? d : zero;  // std::max(0.0, d)
        d = d < one ? d : one;    // std::min(1.0, d)
    }

    // pair(row, col, both lanes) and pair(row, col + 2, both lanes) at once, in four lanes.
    // `col + 3 < size`.
    void row4(int row, int col) const {
        const double py = row;
        v4d d;
        v4l outside;
        depth4(v4d{} + ea.row(py), v4d{} + eb.row(py), v4d{} + ec.row(py),
               v4d{double(col), double(col + 1), double(col + 2), double(col + 3)}, d, outside);
        const v4i covered = ~__builtin_convertvector(outside, v4i);
        const v4f near = __builtin_convertvector(d, v4f);
        const size_t line = static_cast<size_t>(row) * static_cast<size_t>(size);
        raise2(front + line + static_cast<size_t>(col), v2f{near[0], near[1]}, v2i{covered[0], covered[1]});
        raise2(front + line + static_cast<size_t>(col + 2), v2f{near[2], near[3]},
               v2i{covered[2], covered[3]});
        if (back) {
            const v4f far = __builtin_convertvector(1.0 - d, v4f);
            raise2(back + line + static_cast<size_t>(size - 2 - col), v2f{far[1], far[0]},
                   v2i{covered[1], covered[0]});
            raise2(back + line + static_cast<size_t>(size - 4 - col), v2f{far[3], far[2]},
                   v2i{covered[3], covered[2]});
        }
    }

    // pair(row, col, keep's first two lanes) and pair(row + 1, col, its last two) at once, in four
    // lanes. `row + 1 < size` and `col + 1 < size`.
    void quad(int row, int col, v4l keep) const {
        const double y0 = row, y1 = row + 1;
        const double a0 = ea.row(y0), a1 = ea.row(y1), b0 = eb.row(y0), b1 = eb.row(y1), c0 = ec.row(y0),
                     c1 = ec.row(y1);
        v4d d;
        v4l outside;
        depth4(v4d{a0, a0, a1, a1}, v4d{b0, b0, b1, b1}, v4d{c0, c0, c1, c1},
               v4d{double(col), double(col + 1), double(col), double(col + 1)}, d, outside);
        const v4i covered = __builtin_convertvector(~outside & keep, v4i);
        const v4f near = __builtin_convertvector(d, v4f);
        const size_t line = static_cast<size_t>(row) * static_cast<size_t>(size);
        const size_t next = line + static_cast<size_t>(size);
        raise2(front + line + static_cast<size_t>(col), v2f{near[0], near[1]}, v2i{covered[0], covered[1]});
        raise2(front + next + static_cast<size_t>(col), v2f{near[2], near[3]}, v2i{covered[2], covered[3]});
        if (back) {
            const v4f far = __builtin_convertvector(1.0 - d, v4f);
            const size_t mirrored = static_cast<size_t>(size - 2 - col);
            raise2(back + line + mirrored, v2f{far[1], far[0]}, v2i{covered[1], covered[0]});
            raise2(back + next + mirrored, v2f{far[3], far[2]}, v2i{covered[3], covered[2]});
        }
    }
};

// The depth image seen along camera frame C into `front` (size x size, zero-filled); when `back`
// is given (also zero-filled), also the opposite view's image: at each covered pixel the largest
// 1 - depth, i.e. the farthest surface of this view, stored mirrored (column c at size - 1 - c: see
// render_depth_pair). Built for AVX2 too (common/cpu_clones.h: the same bits, fewer instructions).
CANONFORM_CLONES void rasterize(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Matrix3d& C,
                                int size, float* front, float* back) {
    // Project: pixel coordinates (col, row as doubles; centres at integers) and depth; per vertex
    // also the first pixel column/row at or after it and the last at or before it (ceil and floor,
    // clamped to [-1, size] - enough, as triangles are clipped to [0, size - 1] - so a triangle's
    // pixel box is integer minima and maxima of its corners', the same box as ceil(min) and
    // floor(max) of the coordinates).
    const double inv_h = size / 2.0;
    const Eigen::Index nv = V.rows();
    thread_local std::vector<Projected> scratch;
    scratch.resize(static_cast<size_t>(nv));
    Projected* pv = scratch.data();
    const auto clamp_pixel = [size](double v) {
        return static_cast<int>(std::min(double(size), std::max(-1.0, v)));
    };
    for (Eigen::Index i = 0; i < nv; ++i) {
        const double x = C(0, 0) * V(i, 0) + C(0, 1) * V(i, 1) + C(0, 2) * V(i, 2);
        const double y = C(1, 0) * V(i, 0) + C(1, 1) * V(i, 1) + C(1, 2) * V(i, 2);
        const double w = C(2, 0) * V(i, 0) + C(2, 1) * V(i, 1) + C(2, 2) * V(i, 2);
        Projected& p = pv[i];
        p.q = {(x + 1.0) * inv_h - 0.5, (1.0 - y) * inv_h - 0.5};
        p.z = 0.5 * (1.0 + w);
        p.cx = clamp_pixel(std::ceil(p.q.x));
        p.fx = clamp_pixel(std::floor(p.q.x));
        p.cy = clamp_pixel(std::ceil(p.q.y));
        p.fy = clamp_pixel(std::floor(p.q.y));
    }

    const int lim = size - 1;

    // Four faces at once, one per lane: the box, the area and the edge functions of each, then
    // the four pixels of its box (at most 2 x 2; faces with wider boxes wait for the one-face loop
    // below). Every lane's operations are that loop's, in the same order; a pixel takes the
    // largest depth of the faces that cover it, whatever the order of the faces, so the image is
    // the same bits.
    const Eigen::Index nf = F.rows();
    const int* const fa = F.data();
    const int* const fb = fa + nf;
    const int* const fc = fb + nf;
    float spare[4] = {0, 0, 0, 0};  // where a lane without pixels reads and writes its nothing
    // Faces with wider boxes and the last few, for the loop after this one (in this function's
    // body, so that they too run in its AVX2 clone: a lambda would be built for baseline x86-64).
    thread_local std::vector<Eigen::Index> later;
    later.clear();
    Eigen::Index f = 0;
    for (; f + 4 <= nf; f += 4) {
        const Projected* A[4] = {pv + fa[f], pv + fa[f + 1], pv + fa[f + 2], pv + fa[f + 3]};
        const Projected* B[4] = {pv + fb[f], pv + fb[f + 1], pv + fb[f + 2], pv + fb[f + 3]};
        const Projected* C4[4] = {pv + fc[f], pv + fc[f + 1], pv + fc[f + 2], pv + fc[f + 3]};
#define CANONFORM_LANES(P, field) \
    { P[0]->field, P[1]->field, P[2]->field, P[3]->field }
        const v4i acx = CANONFORM_LANES(A, cx), bcx = CANONFORM_LANES(B, cx), ccx = CANONFORM_LANES(C4, cx);
        const v4i afx = CANONFORM_LANES(A, fx), bfx = CANONFORM_LANES(B, fx), cfx = CANONFORM_LANES(C4, fx);
        const v4i acy = CANONFORM_LANES(A, cy), bcy = CANONFORM_LANES(B, cy), ccy = CANONFORM_LANES(C4, cy);
        const v4i afy = CANONFORM_LANES(A, fy), bfy = CANONFORM_LANES(B, fy), cfy = CANONFORM_LANES(C4, fy);
        const auto vmin = [](v4i x, v4i y) { return x < y ? x : y; };
        const auto vmax = [](v4i x, v4i y) { return x < y ? y : x; };
        const v4i zero_i = {0, 0, 0, 0}, lim_i = zero_i + lim;
        const v4i c0 = vmax(zero_i, vmin(vmin(acx, bcx), ccx)), c1 = vmin(lim_i, vmax(vmax(afx, bfx), cfx));
        const v4i r0 = vmax(zero_i, vmin(vmin(acy, bcy), ccy)), r1 = vmin(lim_i, vmax(vmax(afy, bfy), cfy));
        const v4i in_image = (c0 <= c1) & (r0 <= r1);
        if (!(in_image[0] | in_image[1] | in_image[2] | in_image[3])) continue;
        const v4d ax = CANONFORM_LANES(A, q.x), ay = CANONFORM_LANES(A, q.y), az = CANONFORM_LANES(A, z);
        const v4d bx = CANONFORM_LANES(B, q.x), by = CANONFORM_LANES(B, q.y), bz = CANONFORM_LANES(B, z);
        const v4d cx = CANONFORM_LANES(C4, q.x), cy = CANONFORM_LANES(C4, q.y), cz = CANONFORM_LANES(C4, z);
#undef CANONFORM_LANES
        const v4d zero = v4d{} + 0.0, one = v4d{} + 1.0;
        const v4d area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        const v4d magnitude = area2 < zero ? -area2 : area2;
        const v4i drawn = in_image & __builtin_convertvector(magnitude > v4d{} + 1e-12, v4i);
        const v4i small = drawn & (c1 - c0 < 2) & (r1 - r0 < 2) & (c0 < lim_i) & (r0 < lim_i);
        for (int l = 0; l < 4; ++l)
            if (drawn[l] & ~small[l]) later.push_back(f + l);
        if (!(small[0] | small[1] | small[2] | small[3])) continue;
        const v4d sgn = area2 > zero ? one : -one;
        const v4d inv_area = one / area2;
        // EdgeFn of (p, q) in every lane.
        struct Edge {
            v4d sx, sy, dx, dy, negate;
        };
        const auto edge = [&](v4d px, v4d py, v4d qx, v4d qy) {  // (inlined: it takes vectors)
            const v4l swap = (qx < px) | ((qx == px) & (qy < py));
            Edge e;
            e.sx = swap ? qx : px;
            e.sy = swap ? qy : py;
            e.dx = (swap ? px : qx) - e.sx;
            e.dy = (swap ? py : qy) - e.sy;
            e.negate = swap ? -one : one;
            return e;
        };
        const Edge ea = edge(bx, by, cx, cy), eb = edge(cx, cy, ax, ay), ec = edge(ax, ay, bx, by);
        const v4d y0 = __builtin_convertvector(r0, v4d), y1 = __builtin_convertvector(r0 + 1, v4d);
        const v4d x0 = __builtin_convertvector(c0, v4d), x1 = __builtin_convertvector(c0 + 1, v4d);
        const v4d ta0 = ea.dx * (y0 - ea.sy), ta1 = ea.dx * (y1 - ea.sy);
        const v4d tb0 = eb.dx * (y0 - eb.sy), tb1 = eb.dx * (y1 - eb.sy);
        const v4d tc0 = ec.dx * (y0 - ec.sy), tc1 = ec.dx * (y1 - ec.sy);
        // The depth at one pixel of every lane's box, and whether the face covers it.
        const auto at = [&](v4d ta, v4d tb, v4d tc, v4d px, v4i keep, v4f& near, v4f& far, v4i& covered) {
            const v4d wa = ea.negate * (ta - ea.dy * (px - ea.sx));
            const v4d wb = eb.negate * (tb - eb.dy * (px - eb.sx));
            const v4d wc = ec.negate * (tc - ec.dy * (px - ec.sx));
            const v4l outside = (sgn * wa < zero) | (sgn * wb < zero) | (sgn * wc < zero);
            v4d d = (wa * az + wb * bz + wc * cz) * inv_area;
            d = zero < d ? d : zero;  // std::max(0.0, d)
            d = d < one ? d : one;    // std::min(1.0, d)
            covered = ~__builtin_convertvector(outside, v4i) & keep & small;
            near = __builtin_convertvector(d, v4f);
            far = __builtin_convertvector(one - d, v4f);
        };
        const v4i all = zero_i - 1, wide = c1 > c0, tall = r1 > r0;
        v4f n00, n01, n10, n11, f00, f01, f10, f11;
        v4i k00, k01, k10, k11;
        at(ta0, tb0, tc0, x0, all, n00, f00, k00);
        at(ta0, tb0, tc0, x1, wide, n01, f01, k01);
        at(ta1, tb1, tc1, x0, tall, n10, f10, k10);
        at(ta1, tb1, tc1, x1, tall & wide, n11, f11, k11);
        for (int l = 0; l < 4; ++l) {
            const bool mine = small[l] != 0;
            const size_t line = static_cast<size_t>(r0[l]) * static_cast<size_t>(size);
            const size_t next = line + static_cast<size_t>(size);
            const size_t col = static_cast<size_t>(c0[l]), mirrored = static_cast<size_t>(size - 2 - c0[l]);
            raise2(mine ? front + line + col : spare, v2f{n00[l], n01[l]}, v2i{k00[l], k01[l]});
            raise2(mine ? front + next + col : spare, v2f{n10[l], n11[l]}, v2i{k10[l], k11[l]});
            if (back) {
                raise2(mine ? back + line + mirrored : spare, v2f{f01[l], f00[l]}, v2i{k01[l], k00[l]});
                raise2(mine ? back + next + mirrored : spare, v2f{f11[l], f10[l]}, v2i{k11[l], k10[l]});
            }
        }
    }
    for (; f < nf; ++f) later.push_back(f);
    // One face at a time.
    for (const Eigen::Index face : later) {
        const Projected& pa = pv[F(face, 0)];
        const Projected& pb = pv[F(face, 1)];
        const Projected& pc = pv[F(face, 2)];
        // The pixel centres the triangle's box holds (a face of a fine mesh holds a few at most).
        const int c0 = std::max(0, std::min({pa.cx, pb.cx, pc.cx}));
        const int c1 = std::min(lim, std::max({pa.fx, pb.fx, pc.fx}));
        if (c0 > c1) continue;
        const int r0 = std::max(0, std::min({pa.cy, pb.cy, pc.cy}));
        const int r1 = std::min(lim, std::max({pa.fy, pb.fy, pc.fy}));
        if (r0 > r1) continue;
        const P2& a = pa.q;
        const P2& b = pb.q;
        const P2& c = pc.q;
        const double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (!(std::abs(area2) > 1e-12)) continue;
        // Orientation-independent: scale the edge functions by the sign of the area.
        const double sgn = area2 > 0 ? 1.0 : -1.0;
        const double inv_area = 1.0 / area2;
        const double za = pa.z, zb = pb.z, zc = pc.z;
        const EdgeFn ea(b, c), eb(c, a), ec(a, b);
        const TriangleDepth t{ea, eb, ec, sgn, za, zb, zc, inv_area, size, front, back};
        if (c1 - c0 < 2 && r1 - r0 < 2 && c0 < lim && r0 < lim) {
            // A box of at most 2 x 2 pixels (most faces of a fine mesh): two rows of two, masked,
            // with no branch.
            const std::int64_t wide = c1 > c0 ? -1 : 0, tall = r1 > r0 ? -1 : 0;
            t.quad(r0, c0, v4l{-1, wide, tall, tall & wide});
            continue;
        }
        // Boxes of at least four columns: four pixels at a time along each row, the last four of a
        // row overlapping the ones before (a pixel raised twice to its own depth is unchanged).
        if (c1 - c0 >= 3) {
            for (int row = r0; row <= r1; ++row)
                for (int col = c0; col <= c1; col += 4) t.row4(row, std::min(col, c1 - 3));
            continue;
        }
        // Wider boxes: pairs along each row; a box one column wide at the image's last column is
        // the second lane of the pair before it, and an odd box's last pair overlaps the one
        // before it (both lanes in the box).
        const bool one_column = c0 == c1;
        const int c_last = one_column ? std::min(c0, lim - 1) : c1 - 1;
        const v2l keep = !one_column ? v2l{-1, -1} : c_last == c0 ? v2l{-1, 0} : v2l{0, -1};
        for (int row = r0; row <= r1; ++row)
            for (int col = c0; col <= c1; col += 2) t.pair(row, std::min(col, c_last), keep);
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
