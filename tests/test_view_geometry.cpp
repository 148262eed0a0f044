// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the view-descriptor geometry: view directions, cube rotations, depth rendering and pose
// normalisation (canonform/views).
//
// Include scheme: both -I<root>/filter_canonical and -I<root>/filter_viewdescriptor are on the
// path; "core/<name>.h" resolves to whichever folder has <name>.h (the file names are distinct).
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/views/depth_render.h"
#include "canonform/views/pose_cost.h"
#include "canonform/views/pose_normalization.h"
#include "canonform/views/view_directions.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <set>

namespace cf = canonform;
namespace vw = canonform::views;

namespace {

// Axis-aligned square [x0,x1] x [y0,y1] at height z, two triangles, appended to (V, F).
void add_square(std::vector<Eigen::Vector3d>& P, std::vector<Eigen::Vector3i>& T, double x0, double x1,
                double y0, double y1, double z) {
    const int b = static_cast<int>(P.size());
    P.push_back({x0, y0, z});
    P.push_back({x1, y0, z});
    P.push_back({x1, y1, z});
    P.push_back({x0, y1, z});
    T.push_back({b, b + 1, b + 2});
    T.push_back({b, b + 2, b + 3});
}

cf::Mesh to_mesh(const std::vector<Eigen::Vector3d>& P, const std::vector<Eigen::Vector3i>& T) {
    cf::Mesh m;
    m.V.resize(static_cast<Eigen::Index>(P.size()), 3);
    m.F.resize(static_cast<Eigen::Index>(T.size()), 3);
    for (size_t i = 0; i < P.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = P[i].transpose();
    for (size_t i = 0; i < T.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = T[i].transpose();
    return m;
}

// Cube [-h, h]^3, 12 outward triangles.
cf::Mesh make_cube(double h) {
    cf::Mesh m;
    m.V.resize(8, 3);
    for (int i = 0; i < 8; ++i) m.V.row(i) << ((i & 1) ? h : -h), ((i & 2) ? h : -h), ((i & 4) ? h : -h);
    m.F.resize(12, 3);
    m.F << 0, 2, 1, 1, 2, 3,  // z = -h
        4, 5, 6, 5, 7, 6,     // z = +h
        0, 1, 4, 1, 5, 4,     // y = -h
        2, 6, 3, 3, 6, 7,     // y = +h
        0, 4, 2, 2, 4, 6,     // x = -h
        1, 3, 5, 3, 7, 5;     // x = +h
    return m;
}

double pixel_x(int col, int size) {
    return -1.0 + (col + 0.5) * 2.0 / size;
}
double pixel_y(int row, int size) {
    return 1.0 - (row + 0.5) * 2.0 / size;
}

}  // namespace

// ---------------------------------------------------------------- view directions and rotations

TEST(ViewDirections, SixtySixDistinctUnitVectorsInStableOrder) {
    const auto D = vw::view_directions();
    ASSERT_EQ(D.size(), 66u);
    for (const auto& d : D) EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    double min_sep = 1e9;
    for (size_t i = 0; i < D.size(); ++i)
        for (size_t j = i + 1; j < D.size(); ++j) min_sep = std::min(min_sep, (D[i] - D[j]).norm());
    EXPECT_GT(min_sep, 0.2);  // nearest neighbours on the twice subdivided octahedron: ~0.39
    // The six axes are included; documented order: lexicographic, (-1,0,0) first, (1,0,0) last.
    EXPECT_TRUE(D.front().isApprox(Eigen::Vector3d(-1, 0, 0), 1e-12));
    EXPECT_TRUE(D.back().isApprox(Eigen::Vector3d(1, 0, 0), 1e-12));
    for (size_t i = 0; i + 1 < D.size(); ++i) {
        const Eigen::Vector3d& a = D[i];
        const Eigen::Vector3d& b = D[i + 1];
        const bool less = a.x() < b.x() - 1e-9 ||
                          (std::abs(a.x() - b.x()) < 1e-9 &&
                           (a.y() < b.y() - 1e-9 || (std::abs(a.y() - b.y()) < 1e-9 && a.z() < b.z())));
        EXPECT_TRUE(less) << i;
    }
    // Symmetric under negation (every view has its antipode).
    for (const auto& d : D) {
        double best = 1e9;
        for (const auto& e : D) best = std::min(best, (e + d).norm());
        EXPECT_LT(best, 1e-12);
    }
    // The 18 vertices of the first subdivision are in the set (the 12 edge midpoints).
    int n_mid = 0;
    for (const auto& d : D) {
        const Eigen::Vector3d a = d.cwiseAbs();
        int nz = 0;
        for (int k = 0; k < 3; ++k) nz += std::abs(a[k] - std::sqrt(0.5)) < 1e-12;
        if (nz == 2) ++n_mid;
    }
    EXPECT_EQ(n_mid, 12);
}

TEST(CubeRotations, TwentyFourDistinctProperRotationsIdentityFirst) {
    const auto R = vw::cube_rotations();
    ASSERT_EQ(R.size(), 24u);
    EXPECT_TRUE(R[0].isIdentity(0));
    for (size_t i = 0; i < R.size(); ++i) {
        EXPECT_NEAR((R[i] * R[i].transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
        EXPECT_NEAR(R[i].determinant(), 1.0, 1e-15);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) EXPECT_TRUE(R[i](a, b) == 0 || std::abs(R[i](a, b)) == 1);
        for (size_t j = i + 1; j < R.size(); ++j) EXPECT_GT((R[i] - R[j]).norm(), 1.0);
    }
    // Closed under composition (a group).
    for (const auto& A : R)
        for (const auto& B : R) {
            bool found = false;
            for (const auto& C : R) found = found || (A * B - C).norm() < 1e-12;
            EXPECT_TRUE(found);
        }
}

TEST(RotationViewMaps, EveryRotationPermutesTheViews) {
    const auto D = vw::view_directions();
    const auto R = vw::cube_rotations();
    const auto M = vw::rotation_view_maps();
    ASSERT_EQ(M.size(), 24u);
    for (size_t r = 0; r < M.size(); ++r) {
        ASSERT_EQ(M[r].size(), 66u);
        std::set<int> image(M[r].begin(), M[r].end());
        EXPECT_EQ(image.size(), 66u) << "rotation " << r << " is not a permutation";
        for (size_t i = 0; i < 66; ++i) {
            ASSERT_GE(M[r][i], 0);
            ASSERT_LT(M[r][i], 66);
            EXPECT_LT((D[static_cast<size_t>(M[r][i])] - R[r] * D[i]).norm(), 1e-9);
        }
    }
    for (int i = 0; i < 66; ++i) EXPECT_EQ(M[0][static_cast<size_t>(i)], i);
    // Composition: the map of R_a R_b is map_a after map_b.
    for (size_t a = 0; a < 24; ++a)
        for (size_t b = 0; b < 24; ++b) {
            size_t c = 0;
            while ((R[a] * R[b] - R[c]).norm() > 1e-12) ++c;
            for (size_t i = 0; i < 66; ++i) EXPECT_EQ(M[c][i], M[a][static_cast<size_t>(M[b][i])]);
        }
}

// ---------------------------------------------------------------- depth rendering

TEST(DepthRender, CameraFrameIsARightHandedRotationWithDocumentedUp) {
    for (const auto& d : vw::view_directions()) {
        const Eigen::Matrix3d C = vw::camera_frame(d);
        EXPECT_NEAR((C * C.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
        EXPECT_NEAR(C.determinant(), 1.0, 1e-12);
        EXPECT_TRUE(C.row(2).transpose().isApprox(d, 1e-12));
    }
    const Eigen::Matrix3d Cz = vw::camera_frame(Eigen::Vector3d(0, 0, 2));
    EXPECT_TRUE(Cz.row(1).isApprox(Eigen::RowVector3d(1, 0, 0), 1e-15));   // up = x (tie -> x)
    EXPECT_TRUE(Cz.row(0).isApprox(Eigen::RowVector3d(0, -1, 0), 1e-15));  // right = up x d
    const Eigen::Matrix3d Cx = vw::camera_frame(Eigen::Vector3d(1, 0, 0));
    EXPECT_TRUE(Cx.row(1).isApprox(Eigen::RowVector3d(0, 1, 0), 1e-15));
}

TEST(DepthRender, SphereMatchesAnalyticDepth) {
    const cf::Mesh s = cf::procedural::make_icosphere(5, 0.9);
    const int N = 256;
    for (const Eigen::Vector3d& dir :
         {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 2, -0.5).normalized(), vw::view_directions()[17]}) {
        const vw::DepthImage img = vw::render_depth(s.V, s.F, dir, N);
        ASSERT_EQ(img.size, N);
        ASSERT_EQ(img.depth.size(), static_cast<size_t>(N * N));
        double max_err = 0;
        int n_inside = 0, n_outside_nonzero = 0;
        for (int r = 0; r < N; ++r)
            for (int c = 0; c < N; ++c) {
                const double x = pixel_x(c, N), y = pixel_y(r, N);
                const double rho2 = x * x + y * y;
                const double v = img.at(r, c);
                if (rho2 < 0.85 * 0.85) {
                    max_err = std::max(max_err, std::abs(v - 0.5 * (1 + std::sqrt(0.81 - rho2))));
                    ++n_inside;
                } else if (rho2 > 0.9 * 0.9) {
                    n_outside_nonzero += v != 0.0f;
                }
            }
        EXPECT_GT(n_inside, 29000);
        EXPECT_LT(max_err, 1e-2) << dir.transpose();
        EXPECT_EQ(n_outside_nonzero, 0);
        // The centre is the nearest point: 0.95.
        EXPECT_NEAR(img.at(N / 2, N / 2), 0.95, 2e-3);
        // gray() = round(255 * depth).
        const auto g = img.gray();
        ASSERT_EQ(g.size(), img.depth.size());
        for (size_t i = 0; i < g.size(); i += 97)
            EXPECT_EQ(g[i], static_cast<int>(std::lround(255.0 * img.depth[i])));
    }
}

TEST(DepthRender, CubeAlongZIsAFlatSquare) {
    const cf::Mesh cube = make_cube(0.5);
    for (int N : {256, 100}) {
        const vw::DepthImage img = vw::render_depth(cube.V, cube.F, Eigen::Vector3d(0, 0, 1), N);
        int n_square = 0;
        for (int r = 0; r < N; ++r)
            for (int c = 0; c < N; ++c) {
                const bool in = std::abs(pixel_x(c, N)) < 0.5 && std::abs(pixel_y(r, N)) < 0.5;
                if (in) {
                    ++n_square;
                    EXPECT_NEAR(img.at(r, c), 0.75f, 1e-6) << r << "," << c;
                } else {
                    EXPECT_EQ(img.at(r, c), 0.0f) << r << "," << c;
                }
            }
        EXPECT_EQ(n_square, (N / 2) * (N / 2));  // 128 x 128 at 256; 50 x 50 at 100
    }
    // From -z the far face of the same cube is hidden, the near one (z = -0.5) is at 0.75 too.
    const vw::DepthImage back = vw::render_depth(cube.V, cube.F, Eigen::Vector3d(0, 0, -1), 64);
    EXPECT_NEAR(back.at(32, 32), 0.75f, 1e-6);
}

TEST(DepthRender, NearerSurfaceOccludesIndependentlyOfOrder) {
    std::vector<Eigen::Vector3d> P;
    std::vector<Eigen::Vector3i> T;
    add_square(P, T, -0.6, 0.6, -0.6, 0.6, 0.0);  // big, behind (from +z)
    add_square(P, T, -0.2, 0.2, -0.2, 0.2, 0.3);  // small, in front
    cf::Mesh m = to_mesh(P, T);
    cf::Mesh rev = m;
    rev.F = m.F.colwise().reverse();  // small square drawn first
    const int N = 128;
    for (const cf::Mesh* mm : {&m, &rev}) {
        const vw::DepthImage front = vw::render_depth(mm->V, mm->F, Eigen::Vector3d(0, 0, 1), N);
        const vw::DepthImage back = vw::render_depth(mm->V, mm->F, Eigen::Vector3d(0, 0, -1), N);
        for (int r = 0; r < N; ++r)
            for (int c = 0; c < N; ++c) {
                const double ax = std::abs(pixel_x(c, N)), ay = std::abs(pixel_y(r, N));
                const bool small = ax < 0.2 && ay < 0.2, big = ax < 0.6 && ay < 0.6;
                const float want_front = small ? 0.65f : big ? 0.5f : 0.0f;
                EXPECT_NEAR(front.at(r, c), want_front, 1e-6) << r << "," << c;
                // From -z the big square (depth 0.5) hides the small one (depth 0.35).
                EXPECT_NEAR(back.at(r, c), big ? 0.5f : 0.0f, 1e-6) << r << "," << c;
            }
    }
    EXPECT_THROW(vw::render_depth(m.V, m.F, Eigen::Vector3d::Zero()), cf::InputError);
    EXPECT_THROW(vw::render_depth(m.V, m.F, Eigen::Vector3d(0, 0, 1), 0), cf::InputError);
}

TEST(DepthRender, SharedEdgesThroughPixelCentresLeaveNoCracks) {
    // A fan of triangles around a pixel centre whose shared edges pass, up to rounding, through
    // many pixel centres (edge directions are small integer vectors; the far ends sit at
    // non-representable fractions, so the edge functions there are rounding noise of either sign).
    // Every centre inside the fan must be drawn (catches a strict fill rule or an edge function
    // whose reversed evaluation is not the exact negation).
    const auto D = vw::view_directions();
    for (int N : {128, 97, 256})
        for (int view : {65, 17, 40}) {
            const Eigen::Matrix3d C = vw::camera_frame(D[static_cast<size_t>(view)]);
            auto world = [&](double col, double row) -> Eigen::Vector3d {  // pixel coords -> world
                const double x = -1.0 + (col + 0.5) * 2.0 / N, y = 1.0 - (row + 0.5) * 2.0 / N;
                return C.transpose() * Eigen::Vector3d(x, y, 0.1);
            };
            std::vector<Eigen::Vector2i> dirs;
            for (int dx = -4; dx <= 4; ++dx)
                for (int dy = -4; dy <= 4; ++dy)
                    if (std::gcd(std::abs(dx), std::abs(dy)) == 1) dirs.push_back({dx, dy});
            std::sort(dirs.begin(), dirs.end(), [](const Eigen::Vector2i& a, const Eigen::Vector2i& b) {
                return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x());
            });
            const int c0 = N / 2, r0 = N / 2;
            const double reach = 0.4 * N;
            std::vector<Eigen::Vector3d> P{world(c0, r0)};
            std::vector<Eigen::Vector3i> T;
            double inner = 1e9;  // radius of a disc inside the fan polygon
            for (const auto& d : dirs) {
                const double t = (reach / d.cast<double>().norm()) / 3.0 * 3.0 + 1.0 / 3.0;
                P.push_back(world(c0 + t * d.x(), r0 + t * d.y()));
                inner = std::min(inner, t * d.cast<double>().norm());
            }
            const int m = static_cast<int>(dirs.size());
            for (int k = 0; k < m; ++k) T.push_back({0, 1 + k, 1 + (k + 1) % m});
            inner *= std::cos(M_PI / 8);  // adjacent directions are less than 45 degrees apart
            const cf::Mesh fan = to_mesh(P, T);
            const vw::DepthImage img = vw::render_depth(fan.V, fan.F, D[static_cast<size_t>(view)], N);
            int holes = 0, checked = 0;
            for (int r = 0; r < N; ++r)
                for (int c = 0; c < N; ++c)
                    if (std::hypot(c - c0, r - r0) < inner - 1) {
                        ++checked;
                        holes += std::abs(img.at(r, c) - 0.55f) > 1e-6f;
                    }
            EXPECT_GT(checked, N * N / 4);
            EXPECT_EQ(holes, 0) << "size " << N << " view " << view;
        }
}

TEST(DepthRender, SixtySixRendersOfATenThousandVertexFigureTiming) {
    const cf::procedural::Figure fig = cf::procedural::make_figure(10000, cf::procedural::figure_pose(3));
    const vw::PoseNormalization pose = vw::normalize_pose(fig.mesh.V, fig.mesh.F);
    const Eigen::MatrixXd X = vw::apply_pose(pose, fig.mesh.V);
    const auto D = vw::view_directions();
    std::vector<vw::DepthImage> imgs;
    imgs.reserve(D.size());
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& d : D) imgs.push_back(vw::render_depth(X, fig.mesh.F, d, 256));
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[ timing   ] 66 depth renders, %d vertices / %d faces, 256x256: %.3f s\n",
                static_cast<int>(X.rows()), static_cast<int>(fig.mesh.F.rows()), sec);
    // Every view sees the figure; views d and -d (indices i and 65 - i) have mirrored silhouettes
    // (orthographic; the camera of -d has the same up vector and the opposite right vector).
    for (size_t i = 0; i < D.size(); ++i) {
        int covered = 0, mismatched = 0;
        const vw::DepthImage& a = imgs[i];
        const vw::DepthImage& b = imgs[65 - i];
        ASSERT_LT((D[i] + D[65 - i]).norm(), 1e-12);
        for (int r = 0; r < 256; ++r)
            for (int c = 0; c < 256; ++c) {
                covered += a.at(r, c) > 0;
                mismatched += (a.at(r, c) > 0) != (b.at(r, 255 - c) > 0);
            }
        EXPECT_GT(covered, 500) << i;
        EXPECT_LE(mismatched, covered / 1000 + 2) << i;
    }
    // Deterministic.
    const vw::DepthImage again = vw::render_depth(X, fig.mesh.F, D[5], 256);
    EXPECT_EQ(again.depth, imgs[5].depth);
    // The time is printed, not asserted: speed is checked by bench/ (canonform_bench_views).
}

// The renderer's definition, pixel by pixel and face by face with no vectors: a pixel
// centre is covered when none of the three edge functions (each evaluated from its canonical
// end, negated when reversed) has the opposite sign of the face's area; its depth is the
// barycentric blend of the corners' depths clamped to [0, 1]; the image keeps the largest.
std::vector<float> plain_render(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Matrix3d& C,
                                int size, bool far) {
    std::vector<float> img(static_cast<size_t>(size) * size, 0.0f);
    const double inv_h = size / 2.0;
    auto project = [&](int v) {
        const Eigen::Vector3d p = V.row(v).transpose();
        const double x = C(0, 0) * p(0) + C(0, 1) * p(1) + C(0, 2) * p(2);
        const double y = C(1, 0) * p(0) + C(1, 1) * p(1) + C(1, 2) * p(2);
        const double w = C(2, 0) * p(0) + C(2, 1) * p(1) + C(2, 2) * p(2);
        return Eigen::Vector3d((x + 1.0) * inv_h - 0.5, (1.0 - y) * inv_h - 0.5, 0.5 * (1.0 + w));
    };
    auto edge = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double px, double py) {
        const bool swap = (b.x() < a.x()) || (b.x() == a.x() && b.y() < a.y());
        const Eigen::Vector3d& s = swap ? b : a;
        const Eigen::Vector3d& t = swap ? a : b;
        const double v = (t.x() - s.x()) * (py - s.y()) - (t.y() - s.y()) * (px - s.x());
        return swap ? -1.0 * v : 1.0 * v;
    };
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d a = project(F(f, 0)), b = project(F(f, 1)), c = project(F(f, 2));
        const double area2 = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        if (!(std::abs(area2) > 1e-12)) continue;
        const double sgn = area2 > 0 ? 1.0 : -1.0, inv_area = 1.0 / area2;
        // Every pixel within a pixel of the corners' extent (none further can be covered).
        auto from = [&](double lo) { return std::max(0, static_cast<int>(std::floor(lo)) - 1); };
        auto to = [&](double hi) { return std::min(size - 1, static_cast<int>(std::ceil(hi)) + 1); };
        for (int row = from(std::min({a.y(), b.y(), c.y()})); row <= to(std::max({a.y(), b.y(), c.y()}));
             ++row)
            for (int col = from(std::min({a.x(), b.x(), c.x()})); col <= to(std::max({a.x(), b.x(), c.x()}));
                 ++col) {
                const double wa = edge(b, c, col, row), wb = edge(c, a, col, row), wc = edge(a, b, col, row);
                if (sgn * wa < 0 || sgn * wb < 0 || sgn * wc < 0) continue;
                const double d =
                    std::min(1.0, std::max(0.0, (wa * a.z() + wb * b.z() + wc * c.z()) * inv_area));
                const float v = static_cast<float>(far ? 1.0 - d : d);
                float& out = img[static_cast<size_t>(row) * size + (far ? size - 1 - col : col)];
                out = std::max(out, v);
            }
    }
    return img;
}

TEST(DepthRender, EveryPixelIsTheBitsOfThePlainDefinition) {
    // The renderer takes a face's pixels two at a time (and a box of up to 2 x 2 in one go): every
    // box shape, odd widths, boxes at the image's last row and column and faces beyond the image
    // must give the plain per-pixel definition's bits, front and mirrored far side alike. A fine
    // figure (boxes of 1-4 pixels at 64), the same figure grown past the image's edges, and a
    // coarse icosphere (wide boxes), at sizes from 2 pixels up.
    const cf::procedural::Figure fig = cf::procedural::make_figure(2000, cf::procedural::figure_pose(2));
    const Eigen::MatrixXd X = vw::apply_pose(vw::normalize_pose(fig.mesh.V, fig.mesh.F), fig.mesh.V);
    const cf::Mesh ball = cf::procedural::make_icosphere(2);
    const std::vector<std::pair<Eigen::MatrixXd, Eigen::MatrixXi>> meshes = {
        {X, fig.mesh.F}, {1.7 * X, fig.mesh.F}, {0.9 * ball.V, ball.F}};
    const auto D = vw::view_directions();
    long covered = 0;
    for (const auto& [V, F] : meshes)
        for (int size : {2, 3, 5, 17, 64})
            for (size_t view : {0, 7, 30}) {
                const Eigen::Matrix3d C = vw::camera_frame(D[view]);
                const auto pair = vw::render_depth_pair(V, F, D[view], size);
                const std::vector<float> front = plain_render(V, F, C, size, false);
                EXPECT_EQ(pair[0].depth, front) << size << " " << view;
                EXPECT_EQ(pair[1].depth, plain_render(V, F, C, size, true)) << size << " " << view;
                EXPECT_EQ(vw::render_depth(V, F, D[view], size).depth, front) << size << " " << view;
                for (float v : front) covered += v > 0;
            }
    EXPECT_GT(covered, 10000);  // the images are not empty
    EXPECT_THROW(vw::render_depth(X, fig.mesh.F, D[0], 1), cf::InputError);
}

TEST(DepthRender, OppositeViewsInOnePassAreTheTwoRenders) {
    const auto D = vw::view_directions();
    const std::vector<int> opposite = vw::opposite_views();
    ASSERT_EQ(opposite.size(), D.size());
    for (size_t i = 0; i < D.size(); ++i) {
        const size_t j = static_cast<size_t>(opposite[i]);
        EXPECT_EQ(D[j], Eigen::Vector3d(-D[i])) << i;  // exactly
        EXPECT_EQ(static_cast<size_t>(opposite[j]), i);
        EXPECT_NE(i, j);
    }
    const cf::procedural::Figure fig = cf::procedural::make_figure(10000, cf::procedural::figure_pose(3));
    const Eigen::MatrixXd X = vw::apply_pose(vw::normalize_pose(fig.mesh.V, fig.mesh.F), fig.mesh.V);
    long covered = 0, coverage_differs = 0, gray_differs = 0;
    double largest = 0;
    // The renderer that checks the mesh once renders the same pairs into reused (dirty) buffers.
    const vw::DepthRenderer renderer(X, fig.mesh.F, 256);
    std::vector<float> front(256 * 256, 0.5f), back_buffer(256 * 256, 0.5f);
    for (size_t i = 0; i < D.size(); ++i) {
        const size_t j = static_cast<size_t>(opposite[i]);
        if (j < i) continue;
        const auto pair = vw::render_depth_pair(X, fig.mesh.F, D[i], 256);
        EXPECT_EQ(pair[0].depth, vw::render_depth(X, fig.mesh.F, D[i], 256).depth) << i;  // the same bits
        renderer.pair_into(D[i], front.data(), back_buffer.data());
        EXPECT_EQ(front, pair[0].depth) << i;
        EXPECT_EQ(back_buffer, pair[1].depth) << i;
        const vw::DepthImage back = vw::render_depth(X, fig.mesh.F, D[j], 256);
        const auto g1 = pair[1].gray(), g2 = back.gray();
        for (size_t k = 0; k < back.depth.size(); ++k) {
            const bool a = pair[1].depth[k] > 0, b = back.depth[k] > 0;
            covered += b;
            coverage_differs += a != b;
            if (a && b) largest = std::max(largest, double(std::abs(pair[1].depth[k] - back.depth[k])));
            gray_differs += g1[k] != g2[k];
        }
    }
    std::printf(
        "[ measure  ] opposite views in one pass against their own renders (33 pairs, 10k figure): "
        "%ld covered pixels, coverage differs at %ld, depth differs by at most %.2g, 8-bit view at %ld\n",
        covered, coverage_differs, largest, gray_differs);
    // A centre exactly on an edge may fall either way, a depth may differ in its last bits.
    EXPECT_LE(coverage_differs, covered / 10000 + 2);
    EXPECT_LE(largest, 1e-6);
    EXPECT_LE(gray_differs, covered / 10000 + 2);
    // An empty face list gives two empty images; bad input is refused as by render_depth.
    const auto empty = vw::render_depth_pair(X, Eigen::MatrixXi(0, 3), D[0], 16);
    EXPECT_EQ(empty[1].depth, std::vector<float>(256, 0.f));
    EXPECT_THROW(vw::render_depth_pair(X, fig.mesh.F, Eigen::Vector3d::Zero()), cf::InputError);
    EXPECT_THROW(renderer.pair_into(Eigen::Vector3d::Zero(), front.data(), back_buffer.data()),
                 cf::InputError);
    Eigen::MatrixXd bad = X;
    bad(5, 1) = std::nan("");
    EXPECT_THROW(vw::DepthRenderer(bad, fig.mesh.F, 256), cf::InputError);
    EXPECT_THROW(vw::DepthRenderer(X, fig.mesh.F, 0), cf::InputError);
    Eigen::MatrixXi out_of_range = fig.mesh.F;
    out_of_range(7, 2) = static_cast<int>(X.rows());
    EXPECT_THROW(vw::DepthRenderer(X, out_of_range, 256), cf::InputError);
}

// ---------------------------------------------------------------- pose normalisation

namespace {

void expect_pose_invariant(const cf::Mesh& mesh, std::uint64_t seed, bool* used_rect) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Eigen::Matrix3d Q =
        Eigen::Quaterniond(Eigen::Vector4d(u(g), u(g), u(g), u(g)).normalized()).toRotationMatrix();
    const double s = 0.3 + 2.0 * std::abs(u(g));
    const Eigen::RowVector3d t(5 * u(g), 5 * u(g), 5 * u(g));
    const Eigen::MatrixXd V2 = ((mesh.V * Q.transpose()) * s).rowwise() + t;

    const vw::PoseNormalization p1 = vw::normalize_pose(mesh.V, mesh.F);
    const vw::PoseNormalization p2 = vw::normalize_pose(V2, mesh.F);
    const Eigen::MatrixXd X1 = vw::apply_pose(p1, mesh.V);
    const Eigen::MatrixXd X2 = vw::apply_pose(p2, V2);
    EXPECT_EQ(p1.used_rectilinearity, p2.used_rectilinearity);
    EXPECT_LT((X1 - X2).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_NEAR(p1.scale / p2.scale, s, 1e-9);
    // Normalised: mean at the origin, largest radius 1, proper rotation.
    EXPECT_LT(X1.colwise().mean().norm(), 1e-12);
    EXPECT_NEAR(X1.rowwise().norm().maxCoeff(), 1.0, 1e-12);
    EXPECT_NEAR(p1.R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((p1.R * p1.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    // The rectilinearity pose does not have a larger projected area than the PCA pose, and the
    // rule is the documented one.
    EXPECT_LE(p1.rect_projected_area, p1.pca_projected_area + 1e-12);
    EXPECT_EQ(p1.used_rectilinearity, p1.rect_cost < p1.pca_cost);
    EXPECT_NEAR(vw::projected_area_ratio(mesh.V, mesh.F, p1.used_rectilinearity ? p1.R : p1.R),
                p1.used_rectilinearity ? p1.rect_projected_area : p1.pca_projected_area, 1e-9);
    // Canonical axes: second moments decreasing.
    const Eigen::RowVector3d m2 = X1.array().square().colwise().mean();
    EXPECT_GE(m2[0], m2[1]);
    EXPECT_GE(m2[1], m2[2]);
    if (used_rect) *used_rect = p1.used_rectilinearity;
}

}  // namespace

TEST(PoseNormalization, FigureIsInvariantToSimilarityTransforms) {
    int n_rect = 0, n = 0;
    for (int pose_id : {0, 2, 3, 4, 5, 11}) {
        const cf::procedural::Figure fig =
            cf::procedural::make_figure(2000, cf::procedural::figure_pose(pose_id));
        bool used_rect = false;
        SCOPED_TRACE(pose_id);
        expect_pose_invariant(fig.mesh, 100 + static_cast<std::uint64_t>(pose_id), &used_rect);
        n_rect += used_rect;
        ++n;
    }
    std::printf("[ info     ] rectilinearity pose chosen for %d of %d figures\n", n_rect, n);
}

TEST(PoseNormalization, BoxLikeShapeIsAlignedByRectilinearity) {
    // A rotated cube: PCA is degenerate (isotropic covariance), rectilinearity aligns the faces
    // with the axes (projected area ratio 1) and wins by bounding-box volume.
    cf::Mesh cube = make_cube(1.0);
    const Eigen::Matrix3d Q =
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    cube.V = cube.V * Q.transpose();
    const vw::PoseNormalization p = vw::normalize_pose(cube.V, cube.F);
    EXPECT_TRUE(p.used_rectilinearity);
    EXPECT_NEAR(p.rect_projected_area, 1.0, 1e-9);
    const Eigen::MatrixXd X = vw::apply_pose(p, cube.V);
    for (Eigen::Index i = 0; i < X.rows(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(X(i, k)), 1.0 / std::sqrt(3.0), 1e-6);
}

TEST(PoseNormalization, RejectsBadInput) {
    const cf::Mesh s = cf::procedural::make_icosphere(1);
    EXPECT_THROW(vw::normalize_pose(s.V, Eigen::MatrixXi(0, 3)), cf::InputError);
    Eigen::MatrixXd bad = s.V;
    bad(3, 1) = std::nan("");
    EXPECT_THROW(vw::normalize_pose(bad, s.F), cf::InputError);
    bad(3, 1) = std::numeric_limits<double>::infinity();
    EXPECT_THROW(vw::normalize_pose(bad, s.F), cf::InputError);
    EXPECT_THROW(vw::normalize_pose(Eigen::MatrixXd::Zero(s.V.rows(), 3), s.F), cf::InputError);
    vw::PoseOptions o;
    o.restarts = 0;
    EXPECT_THROW(vw::normalize_pose(s.V, s.F, o), cf::InputError);
    o.restarts = 8;
    o.direction_bins = -1;
    EXPECT_THROW(vw::normalize_pose(s.V, s.F, o), cf::InputError);
}

TEST(PoseNormalization, BinnedCoarseSearchFindsTheSameRectilinearity) {
    // The coarse restarts on direction-binned area vectors, refined on every face, reach the
    // projected-area minimum of the search over every face (within the refinement's tolerance).
    for (int pose = 0; pose < 4; ++pose) {
        const cf::procedural::Figure fig =
            cf::procedural::make_figure(3000, cf::procedural::figure_pose(pose));
        vw::PoseOptions exact;
        exact.direction_bins = 0;
        const vw::PoseNormalization a = vw::normalize_pose(fig.mesh.V, fig.mesh.F);
        const vw::PoseNormalization b = vw::normalize_pose(fig.mesh.V, fig.mesh.F, exact);
        EXPECT_NEAR(a.rect_projected_area, b.rect_projected_area, 1e-3 * b.rect_projected_area)
            << "pose " << pose;
        EXPECT_DOUBLE_EQ(a.pca_cost, b.pca_cost);
        EXPECT_LE(a.rect_projected_area, a.pca_projected_area + 1e-12);
    }
}

TEST(PoseNormalization, ProjectedAreaRatioIsTheSumOverFaces) {
    // projected_area_ratio (and the rectilinearity cost it shares, evaluated on coordinate arrays
    // with SIMD packets) equals the plain sum over faces of |R a_t|_1 / sum_t |a_t|.
    const cf::procedural::Figure fig = cf::procedural::make_figure(3000, cf::procedural::figure_pose(1));
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(Eigen::Vector4d(0.3, -0.5, 0.2, 0.7).normalized()).toRotationMatrix();
    double projected = 0, area = 0;
    for (Eigen::Index f = 0; f < fig.mesh.F.rows(); ++f) {
        const Eigen::Vector3d p0 = fig.mesh.V.row(fig.mesh.F(f, 0)).transpose(),
                              p1 = fig.mesh.V.row(fig.mesh.F(f, 1)).transpose(),
                              p2 = fig.mesh.V.row(fig.mesh.F(f, 2)).transpose();
        const Eigen::Vector3d a = 0.5 * (p1 - p0).cross(p2 - p0);
        projected += (R * a).cwiseAbs().sum();
        area += a.norm();
    }
    EXPECT_NEAR(vw::projected_area_ratio(fig.mesh.V, fig.mesh.F, R), projected / area,
                1e-12 * projected / area);
    EXPECT_GT(projected / area, 1.0);  // |x|_1 >= |x|_2 for every face
}

TEST(PoseNormalization, RectilinearitySumIsEigensSumOfTheArrayBitForBit) {
    // The objective's sum, vectorised by hand (4 or 8 terms at a time), takes the order of Eigen's
    // sum() of the array expression in packets of two doubles (the x86-64 baseline the pose was
    // computed with), for every length's remainder mod 4 and on large arrays.
    if (Eigen::internal::packet_traits<double>::size != 2 ||
        !Eigen::internal::packet_traits<double>::Vectorizable)
        GTEST_SKIP() << "Eigen here sums doubles in packets of another size";
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> coord(-1.0, 1.0), scale(-12.0, 3.0);
    for (const Eigen::Index n :
         {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15,   16,    17,   18,
          19, 20, 21, 22, 23, 31, 32, 33, 34, 35, 63, 64, 65, 66, 67, 1001, 19998, 19999}) {
        Eigen::ArrayXd x(n), y(n), z(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            // Magnitudes over 15 orders, so that the sum rounds differently in another order.
            x[i] = coord(gen) * std::pow(10.0, scale(gen));
            y[i] = coord(gen) * std::pow(10.0, scale(gen));
            z[i] = i % 7 == 3 ? -0.0 : coord(gen) * std::pow(10.0, scale(gen));
        }
        for (int r = 0; r < 3; ++r) {
            const Eigen::Matrix3d Q =
                Eigen::Quaterniond(
                    Eigen::Vector4d(coord(gen), coord(gen), coord(gen), coord(gen)).normalized())
                    .toRotationMatrix();
            const double eigen = ((Q(0, 0) * x + Q(0, 1) * y + Q(0, 2) * z).abs() +
                                  (Q(1, 0) * x + Q(1, 1) * y + Q(1, 2) * z).abs() +
                                  (Q(2, 0) * x + Q(2, 1) * y + Q(2, 2) * z).abs())
                                     .sum();
            const double ours = vw::detail::rectilinearity_sum(x.data(), y.data(), z.data(), n, Q);
            EXPECT_EQ(std::memcmp(&eigen, &ours, sizeof(double)), 0)
                << "n " << n << ": " << eigen << " against " << ours << " (difference " << ours - eigen
                << ")";
        }
    }
}

TEST(PoseNormalization, SameBitsWhateverTheCpuCacheSizes) {
    // Eigen blocks a matrix product by the L1 cache size that CPUID reports; the pose does not
    // depend on it (the covariance is summed row by row; no libm either, see the header).
    for (int pose_id : {4, 5}) {
        const cf::procedural::Figure fig =
            cf::procedural::make_figure(2000, cf::procedural::figure_pose(pose_id));
        const auto poses =
            cf::test::under_l1_cache_sizes([&] { return vw::normalize_pose(fig.mesh.V, fig.mesh.F); });
        for (const auto& p : poses) {
            EXPECT_EQ(p.used_rectilinearity, poses[0].used_rectilinearity);
            EXPECT_TRUE((p.R.array() == poses[0].R.array()).all()) << "pose " << pose_id << "\n"
                                                                   << p.R - poses[0].R;
            EXPECT_EQ(p.rect_projected_area, poses[0].rect_projected_area);
        }
    }
}
