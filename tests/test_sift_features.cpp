// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of sift_features.h: the canonform SIFT extractor (Lowe 2004, our implementation) by its
// properties - repeatability under exact rotations and flips of the view, descriptors under a small
// rotation, the scale of a blob of known size, agreement with OpenCV's descriptors on the same
// keypoints, determinism and independence of the thread count - and the choice of extractor.
#include "canonform/views/sift_features.h"

#include "canonform/common/parallel.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/views/depth_render.h"
#include "canonform/views/opencv_sift.h"
#include "canonform/views/sift_pyramid.h"
#include "canonform/views/view_directions.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace canonform;
using namespace canonform::views;
using namespace canonform::procedural;

namespace {

#ifndef CANONFORM_WITHOUT_OPENCV
// The test program has OpenCV: its extractor is registered as the tool registers it.
const bool kOpenCVRegistered = (register_opencv_sift(), true);
#endif

using Image = std::vector<float>;
constexpr int kN = 256;

// A synthetic depth view in [0, 1] evaluated at view position (x, y) in [-1, 1]^2 (x right, y
// down), 0 = background: a sphere with nine Gaussian bumps, or a capsule stick figure. `turn`
// rotates the scene about the view's centre (radians, clockwise on screen).
Image synthetic(bool bumps, double turn = 0, int n = kN) {
    Image img(static_cast<std::size_t>(n) * n, 0.f);
    const double ct = std::cos(turn), st = std::sin(turn);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const double u = (c + 0.5) / n * 2 - 1, v = (r + 0.5) / n * 2 - 1;
            const double x = ct * u + st * v, y = -st * u + ct * v;  // the scene point seen at (u, v)
            const double z = test::synthetic_scene_height(bumps, x, y);
            if (z > -1.5)
                img[static_cast<std::size_t>(r) * n + c] =
                    static_cast<float>(std::clamp(0.5 + 0.4 * z, 0.01, 1.0));
        }
    return img;
}

// Depth views of a procedural figure (pose 2) from `count` of the 66 view directions; `turn` turns
// the figure about each view direction first, so that the view turns by `turn` clockwise on screen
// about the image centre (pixel (n - 1) / 2, the projection of the origin).
std::vector<Image> figure_views(int count, double turn = 0) {
    const Figure fig = make_figure(3000, figure_pose(2));
    Eigen::MatrixXd V = fig.mesh.V.rowwise() - fig.mesh.V.colwise().mean();
    V /= 1.05 * V.rowwise().norm().maxCoeff();
    std::vector<Image> out;
    const auto dirs = view_directions();
    for (int i = 0; i < count; ++i) {
        const Eigen::Vector3d d = dirs[static_cast<size_t>(i * 7 % 66)].normalized();
        // The camera's up vector is image -y: a rotation by -turn about d (right-handed) turns the
        // image by turn clockwise on screen.
        const Eigen::Matrix3d R = Eigen::AngleAxisd(-turn, d).toRotationMatrix();
        const Eigen::MatrixXd W = V * R.transpose();
        out.push_back(render_depth(W, fig.mesh.F, d, kN).depth);
    }
    return out;
}

// The view turned 90 degrees clockwise on screen: pixel (x, y) goes to (n - 1 - y, x).
Image rotate90(const Image& a, int n = kN) {
    Image b(a.size());
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            b[static_cast<size_t>(x) * n + (n - 1 - y)] = a[static_cast<size_t>(y) * n + x];
    return b;
}

// The view mirrored left to right: pixel (x, y) goes to (n - 1 - x, y).
Image flip(const Image& a, int n = kN) {
    Image b(a.size());
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            b[static_cast<size_t>(y) * n + (n - 1 - x)] = a[static_cast<size_t>(y) * n + x];
    return b;
}

double angle_gap(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 360.0);
    return std::min(d, 360.0 - d);
}

// The fraction of `a`'s keypoints with a keypoint of `b` at the mapped position (within a third of
// the keypoint's sigma, at least 0.3 pixel), of the same size (5%) and mapped angle (3 degrees).
template <class Map>
double repeat_rate(const SiftFeatures& a, const SiftFeatures& b, Map map,
                   std::vector<std::pair<size_t, size_t>>* pairs = nullptr) {
    if (a.keypoints.empty()) return 0;
    size_t hit = 0;
    for (size_t i = 0; i < a.keypoints.size(); ++i) {
        const SiftKeypoint& k = a.keypoints[i];
        double mx, my, ma;
        map(k, mx, my, ma);
        const double tol = std::max(0.3, k.size / 6.0);
        for (size_t j = 0; j < b.keypoints.size(); ++j) {
            const SiftKeypoint& q = b.keypoints[j];
            if (std::hypot(q.x - mx, q.y - my) < tol && std::abs(std::log(q.size / k.size)) < 0.05 &&
                angle_gap(q.angle, ma) < 3) {
                ++hit;
                if (pairs) pairs->push_back({i, j});
                break;
            }
        }
    }
    return double(hit) / double(a.keypoints.size());
}

double cosine(const Eigen::Ref<const Eigen::RowVectorXf>& a, const Eigen::Ref<const Eigen::RowVectorXf>& b) {
    return a.dot(b) / (a.norm() * b.norm());
}

// The format every extractor writes: integers 0-255, L2 norm about 512.
void expect_descriptor_format(const SiftDescriptors& d) {
    EXPECT_TRUE(d.allFinite());
    if (d.rows() == 0) return;
    EXPECT_GE(d.minCoeff(), 0.f);
    EXPECT_LE(d.maxCoeff(), 255.f);
    for (Eigen::Index r = 0; r < d.rows(); ++r) {
        EXPECT_NEAR(d.row(r).norm(), 512.f, 40.f);
        EXPECT_EQ(d.row(r), d.row(r).array().round().matrix());
    }
}

}  // namespace

TEST(Sift, BlankImageHasNoKeypointsAndBadInputIsRefused) {
    EXPECT_EQ(sift_descriptors(Image(kN * kN, 0.f), kN).rows(), 0);
    EXPECT_EQ(sift_descriptors(std::vector<std::uint8_t>(64 * 64, 200), 64).rows(), 0);
    EXPECT_THROW(sift_descriptors(Image(10, 0.f), kN), InputError);
    EXPECT_THROW(sift_descriptors(Image{}, 0), InputError);
    Image nan = synthetic(true);
    nan[5] = std::nanf("");
    EXPECT_THROW(sift_features(nan, kN), InputError);
    const Image img = synthetic(true);
    for (auto bad : std::vector<void (*)(SiftOptions&)>{
             [](SiftOptions& o) { o.octave_layers = 0; }, [](SiftOptions& o) { o.sigma = 0; },
             [](SiftOptions& o) { o.contrast_threshold = -1; }, [](SiftOptions& o) { o.edge_threshold = 0; },
             [](SiftOptions& o) { o.max_features = -1; }, [](SiftOptions& o) { o.input_blur = 0.8; }}) {
        SiftOptions o;
        bad(o);
        EXPECT_THROW(sift_features(img, kN, o), InputError);
    }
}

TEST(Sift, BackendNames) {
    EXPECT_EQ(SiftOptions{}.backend, SiftBackend::Canonform);  // the default needs no other library
    for (const auto& name : sift_backend_names())
        EXPECT_EQ(sift_backend_name(parse_sift_backend(name)), name);
    EXPECT_EQ(builtin_sift_backend_names(), std::vector<std::string>{"canonform"});
    EXPECT_TRUE(sift_backend_available(SiftBackend::Canonform));
#ifdef CANONFORM_WITHOUT_OPENCV  // (the Windows build) no OpenCV extractor to register
    EXPECT_FALSE(sift_backend_available(SiftBackend::OpenCV));
    SiftOptions o;
    o.backend = SiftBackend::OpenCV;
    const std::string refused =
        test::message_of([&] { sift_features(std::vector<float>(64 * 64, 0.5f), 64, o); });
    EXPECT_NE(refused.find("'opencv' is not part of this program (canonform are"), std::string::npos)
        << refused;
#else
    EXPECT_TRUE(sift_backend_available(SiftBackend::OpenCV));  // registered by this program
#endif
    EXPECT_NE(test::message_of([] { parse_sift_backend("surf"); }).find("canonform, opencv"),
              std::string::npos);
    const std::string removed = test::message_of([] { parse_sift_backend("opencv-octave0-fine"); });
    EXPECT_NE(removed.find("removed"), std::string::npos) << removed;
    EXPECT_NE(removed.find("'canonform'"), std::string::npos) << removed;
}

// Keypoints, their octaves and descriptors in the documented format; the approximate octave -1
// holds the finest keypoints; an 8-bit image is its values / 255; max_features keeps the strongest.
TEST(Sift, KeypointsAndDescriptorsAsDocumented) {
    for (const bool bumps : {true, false}) {
        const Image img = synthetic(bumps);
        const SiftFeatures f = sift_features(img, kN);
        ASSERT_EQ(static_cast<size_t>(f.descriptors.rows()), f.keypoints.size());
        ASSERT_GE(f.keypoints.size(), 10u);
        expect_descriptor_format(f.descriptors);
        std::map<int, int> per_octave;
        std::map<int, float> smallest, largest;
        for (const SiftKeypoint& k : f.keypoints) {
            EXPECT_GE(k.x, 0.f);
            EXPECT_LE(k.x, kN - 1.f);
            EXPECT_GE(k.y, 0.f);
            EXPECT_LE(k.y, kN - 1.f);
            EXPECT_GE(k.angle, 0.f);
            EXPECT_LT(k.angle, 360.f);
            EXPECT_GE(k.response, static_cast<float>(kDefaultContrastThreshold / 3));
            ++per_octave[k.octave];
            smallest.try_emplace(k.octave, k.size);
            largest.try_emplace(k.octave, k.size);
            smallest[k.octave] = std::min(smallest[k.octave], k.size);
            largest[k.octave] = std::max(largest[k.octave], k.size);
        }
        EXPECT_GT(per_octave[0], 0);
        // Octave o >= 0 holds sizes 2 sigma0 2^o 2^(j/3) for DoG images j = 1..3 and offsets up to
        // 0.6; octave -1 2 (sigma0 / 2) 2^(j/2), j = 1..2.
        for (const auto& [o, n] : per_octave) {
            const double lo = o < 0 ? 2 * 0.8 * std::pow(2.0, 0.4 / 2)
                                    : 2 * 1.6 * std::ldexp(1.0, o) * std::pow(2.0, 0.4 / 3);
            const double hi = o < 0 ? 2 * 0.8 * std::pow(2.0, 2.6 / 2)
                                    : 2 * 1.6 * std::ldexp(1.0, o) * std::pow(2.0, 3.6 / 3);
            EXPECT_GE(smallest[o], 0.99 * lo) << "octave " << o;
            EXPECT_LE(largest[o], 1.01 * hi) << "octave " << o;
        }
        std::printf("[sift] %s: %zu keypoints:", bumps ? "bumpy sphere" : "stick figure", f.keypoints.size());
        for (const auto& [o, n] : per_octave) std::printf(" octave %d: %d", o, n);
        std::printf("\n");
        SiftOptions coarse;
        coarse.fine_octave = false;
        const SiftFeatures c = sift_features(img, kN, coarse);
        for (const SiftKeypoint& k : c.keypoints) EXPECT_GE(k.octave, 0);
        EXPECT_EQ(static_cast<int>(c.keypoints.size()),
                  static_cast<int>(f.keypoints.size()) - per_octave[-1]);
        SiftOptions few;
        few.max_features = 5;
        const SiftFeatures s = sift_features(img, kN, few);
        ASSERT_EQ(s.keypoints.size(), 5u);
        std::vector<float> r;
        for (const SiftKeypoint& k : f.keypoints) r.push_back(k.response);
        std::sort(r.rbegin(), r.rend());
        for (const SiftKeypoint& k : s.keypoints) EXPECT_GE(k.response, r[4]);
    }
    long fine = 0;  // the approximate octave -1 holds keypoints of rendered views
    for (const Image& v : figure_views(8))
        for (const SiftKeypoint& k : depth_sift_features(v, kN).keypoints) fine += k.octave == -1;
    EXPECT_GT(fine, 0);
    std::vector<std::uint8_t> gray(kN * kN);
    Image as_float(kN * kN);
    const Image img = synthetic(true);
    for (size_t i = 0; i < gray.size(); ++i) {
        gray[i] = static_cast<std::uint8_t>(std::lround(255 * img[i]));
        as_float[i] = gray[i] / 255.f;
    }
    EXPECT_TRUE(sift_descriptors(gray, kN) == sift_descriptors(as_float, kN));
    EXPECT_TRUE(depth_sift_descriptors(img, kN) == sift_descriptors(gray, kN));  // a depth view as 8 bits
}

// Lowe's keypoints are covariant with rotations of the image. A quarter turn and a mirror image
// permute the pixels exactly, so the keypoints of the approximate octave -1, found on the view's own
// grid, must come back at the mapped positions, with the same size and the mapped angle - all but a
// few, which the rounding of the other summation order of the separable blur can tip (the rows of
// the turned view are the columns of the view). Octaves 0 and up lie on other grids: the doubled
// image's (the view at i - 1/4) and every second pixel of it. A quarter turn or a mirror image maps
// such a grid onto one half a pixel of the octave away, so there the keypoints are those of a
// slightly different sampling: most come back, within the looser tolerance of the octave.
TEST(Sift, KeypointsRepeatUnderQuarterTurnsAndMirroring) {
    std::vector<Image> views = figure_views(8);
    views.push_back(synthetic(true));
    views.push_back(synthetic(false));
    size_t fine_total = 0, coarse_total = 0, fine_hit[2] = {0, 0}, coarse_hit[2] = {0, 0};
    for (const Image& v : views) {
        const SiftFeatures a = sift_features(v, kN);
        const SiftFeatures moved[2] = {sift_features(rotate90(v), kN), sift_features(flip(v), kN)};
        for (const SiftKeypoint& k : a.keypoints) {
            const bool grid = k.octave < 0;
            (grid ? fine_total : coarse_total) += 1;
            for (int t = 0; t < 2; ++t) {
                const double x = t == 0 ? kN - 1 - k.y : kN - 1 - k.x, y = t == 0 ? k.x : k.y;
                const double angle =
                    t == 0 ? std::fmod(k.angle + 90.0, 360.0) : std::fmod(540.0 - k.angle, 360.0);
                const double scale = std::ldexp(1.0, std::max(0, k.octave));
                const double tol_xy = grid ? 0.01 : 0.75 * scale, tol_size = grid ? 1e-4 : 0.1,
                             tol_angle = grid ? 0.05 : 10;
                bool found = false;
                for (const SiftKeypoint& q : moved[t].keypoints)
                    found = found || (q.octave == k.octave && std::hypot(q.x - x, q.y - y) < tol_xy &&
                                      std::abs(std::log(q.size / k.size)) < tol_size &&
                                      angle_gap(q.angle, angle) < tol_angle);
                (grid ? fine_hit[t] : coarse_hit[t]) += found;
            }
        }
    }
    const auto rate = [](size_t hit, size_t n) { return double(hit) / double(std::max<size_t>(n, 1)); };
    std::printf(
        "[sift] 10 views: of %zu keypoints at octave -1, %.3f come back under a quarter turn and %.3f "
        "mirrored; of %zu at octaves >= 0, %.3f and %.3f\n",
        fine_total, rate(fine_hit[0], fine_total), rate(fine_hit[1], fine_total), coarse_total,
        rate(coarse_hit[0], coarse_total), rate(coarse_hit[1], coarse_total));
    ASSERT_GE(fine_total, 10u);
    ASSERT_GE(coarse_total, 100u);
    for (int t = 0; t < 2; ++t) {
        EXPECT_GE(rate(fine_hit[t], fine_total), 0.9);
        EXPECT_GE(rate(coarse_hit[t], coarse_total), 0.6);
    }
}

// Under a small rotation of the scene (10 degrees, re-rendered, so the pixels differ) a keypoint found
// in both views has nearly the same descriptor: its nearest descriptor among all of the other view's
// is its own match for most keypoints, and the matched descriptors are close.
TEST(Sift, MatchedDescriptorsAgreeUnderASmallRotation) {
    const double turn = 10.0 * 3.14159265358979 / 180;
    const std::vector<Image> before = figure_views(8), after = figure_views(8, turn);
    size_t pairs_total = 0, nearest_is_match = 0, keypoints = 0;
    double cos_sum = 0;
    const double c = std::cos(turn), s = std::sin(turn), h = (kN - 1) / 2.0;
    for (size_t v = 0; v < before.size(); ++v) {
        const SiftFeatures a = sift_features(before[v], kN), b = sift_features(after[v], kN);
        keypoints += a.keypoints.size();
        for (size_t i = 0; i < a.keypoints.size(); ++i) {
            // A point seen at offset p from the centre is seen at R(turn) p (clockwise on screen).
            const SiftKeypoint& k = a.keypoints[i];
            const double u = k.x - h, w = k.y - h, x = h + c * u - s * w, y = h + s * u + c * w;
            const double ang = std::fmod(k.angle + 10.0, 360.0);
            for (size_t j = 0; j < b.keypoints.size(); ++j) {
                const SiftKeypoint& q = b.keypoints[j];
                if (std::hypot(q.x - x, q.y - y) < std::max(0.5, q.size / 8.0) &&
                    std::abs(std::log(q.size / k.size)) < 0.1 && angle_gap(q.angle, ang) < 5) {
                    const auto da = a.descriptors.row(static_cast<Eigen::Index>(i));
                    Eigen::Index best = 0;
                    (b.descriptors.rowwise() - da).rowwise().squaredNorm().minCoeff(&best);
                    nearest_is_match += static_cast<size_t>(best) == j;
                    cos_sum += cosine(da, b.descriptors.row(static_cast<Eigen::Index>(j)));
                    ++pairs_total;
                    break;
                }
            }
        }
    }
    ASSERT_GE(pairs_total, 50u);
    const double nn = double(nearest_is_match) / double(pairs_total),
                 mean_cos = cos_sum / double(pairs_total);
    std::printf(
        "[sift] 10-degree turn, 8 figure views: %zu of %zu keypoints found again; the nearest descriptor is "
        "the "
        "match's for %.3f, mean cosine %.3f\n",
        pairs_total, keypoints, nn, mean_cos);
    EXPECT_GE(nn, 0.85);
    EXPECT_GE(mean_cos, 0.93);
}

// A Gaussian blob of sigma s is an extremum of D at the centre and at the scale sigma with
// sigma sqrt(k) = s: D(sigma) = L(k sigma) - L(sigma) is largest in magnitude where
// 1/(s^2 + sigma^2) - 1/(s^2 + k^2 sigma^2) is, i.e. sigma^2 = s^2 / k (k = 2^(1/3) in octaves 0
// and up, 2^(1/2) in the approximate octave -1).
TEST(Sift, BlobIsFoundAtItsCentreAndScale) {
    for (const double s : {2.0, 3.0, 5.0, 8.0, 13.0, 21.0}) {
        const double cx = 120.3, cy = 131.6;
        Image img(kN * kN);
        for (int r = 0; r < kN; ++r)
            for (int c = 0; c < kN; ++c)
                img[static_cast<size_t>(r) * kN + c] = static_cast<float>(
                    0.6 * std::exp(-((c - cx) * (c - cx) + (r - cy) * (r - cy)) / (2 * s * s)));
        const SiftFeatures f = sift_features(img, kN);
        const SiftKeypoint* best = nullptr;
        for (const SiftKeypoint& q : f.keypoints)
            if (!best || q.response > best->response) best = &q;
        ASSERT_NE(best, nullptr) << "s = " << s;
        const double sigma = best->size / 2, k = std::pow(2.0, best->octave < 0 ? 0.5 : 1.0 / 3);
        std::printf("[sift] blob sigma %.0f: strongest keypoint at (%.2f, %.2f), sigma sqrt(k) %.2f\n", s,
                    best->x, best->y, sigma * std::sqrt(k));
        EXPECT_LT(std::hypot(best->x - cx, best->y - cy), 0.05 * s + 0.1) << "s = " << s;
        EXPECT_NEAR(sigma * std::sqrt(k), s, 0.06 * s) << "s = " << s;
    }
}

// On the same keypoints, our descriptors and OpenCV's (cv::SIFT::compute, public API) describe the
// same patch: for most keypoints the nearest of OpenCV's descriptors of the view is the one of the
// same keypoint. OpenCV describes on its own pyramid from the 8-bit view (doubled for the keypoints
// of octave -1), so the values differ a little.
TEST(Sift, DescriptorsMatchOpenCVsOnTheSameKeypoints) {
#ifdef CANONFORM_WITHOUT_OPENCV
    GTEST_SKIP() << "this build has no OpenCV (the Windows build)";
#endif
    std::vector<Image> views = figure_views(6);
    views.push_back(synthetic(true));
    views.push_back(synthetic(false));
    size_t n = 0, hits = 0;
    double cos_sum = 0;
    for (const Image& v : views) {
        const SiftFeatures f = sift_features(v, kN);
        for (const bool fine : {false, true}) {  // OpenCV doubles the view for octave -1 only
            std::vector<SiftKeypoint> keys;
            std::vector<Eigen::Index> rows;
            for (size_t i = 0; i < f.keypoints.size(); ++i)
                if ((f.keypoints[i].octave < 0) == fine) {
                    keys.push_back(f.keypoints[i]);
                    rows.push_back(static_cast<Eigen::Index>(i));
                }
            if (keys.empty()) continue;
            const SiftDescriptors theirs = opencv_descriptors_at(v, kN, keys);
            ASSERT_EQ(theirs.rows(), static_cast<Eigen::Index>(keys.size()));
            for (size_t i = 0; i < keys.size(); ++i) {
                const auto ours = f.descriptors.row(rows[i]);
                Eigen::Index best = 0;
                (theirs.rowwise() - ours).rowwise().squaredNorm().minCoeff(&best);
                hits += static_cast<size_t>(best) == i;
                cos_sum += cosine(ours, theirs.row(static_cast<Eigen::Index>(i)));
                ++n;
            }
        }
    }
    ASSERT_GE(n, 100u);
    const double rate = double(hits) / double(n);
    std::printf(
        "[sift] against OpenCV's SIFT::compute on our %zu keypoints (8 views): nearest-neighbour rate %.3f, "
        "mean cosine %.3f\n",
        n, rate, cos_sum / double(n));
    EXPECT_GE(rate, 0.85);
    EXPECT_GE(cos_sum / double(n), 0.9);
}

// The same features every time, whatever the number of threads extracting views at once.
TEST(Sift, DeterministicAndIndependentOfTheThreadCount) {
    std::vector<Image> views = figure_views(8);
    views.push_back(synthetic(true));
    std::vector<std::vector<SiftFeatures>> runs;
    for (const int threads : {1, 2, 4}) {  // views handed out in turn to that many threads at once
        std::vector<SiftFeatures> out(views.size());
        std::atomic<size_t> next{0};
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t)
            pool.emplace_back([&] {
                for (size_t i = next++; i < views.size(); i = next++) out[i] = sift_features(views[i], kN);
            });
        for (auto& t : pool) t.join();
        runs.push_back(std::move(out));
    }
    // ... and through the library's parallel loop, as a retrieval run extracts them.
    std::vector<SiftFeatures> looped(views.size());
    ParallelOptions par;
    par.threads = 2;
    parallel_for(
        static_cast<std::ptrdiff_t>(views.size()),
        [&](std::ptrdiff_t i, int) {
            looped[static_cast<size_t>(i)] = sift_features(views[static_cast<size_t>(i)], kN);
        },
        par);
    runs.push_back(std::move(looped));
    for (size_t r = 1; r < runs.size(); ++r)
        for (size_t i = 0; i < views.size(); ++i) {
            const SiftFeatures &a = runs[0][i], &b = runs[r][i];
            ASSERT_EQ(a.keypoints.size(), b.keypoints.size());
            EXPECT_TRUE(a.descriptors == b.descriptors);
            for (size_t k = 0; k < a.keypoints.size(); ++k) {
                EXPECT_EQ(a.keypoints[k].x, b.keypoints[k].x);
                EXPECT_EQ(a.keypoints[k].y, b.keypoints[k].y);
                EXPECT_EQ(a.keypoints[k].size, b.keypoints[k].size);
                EXPECT_EQ(a.keypoints[k].angle, b.keypoints[k].angle);
                EXPECT_EQ(a.keypoints[k].octave, b.keypoints[k].octave);
            }
        }
}

// The extremum scan's row kernels (16 lanes with AVX-512 where the CPU has it) give the portable
// ones' DoG values to the bit and the same candidates, in order: rows of every width from 2 to 70
// (the masked last step), values drawn from a few levels so that ties, zeros of both signs and
// values at the pre-test threshold are common. (On a CPU without AVX-512 both are the portable
// kernels.)
TEST(Sift, RowScanFindsThePortableCandidates) {
    std::mt19937 rng(5);
    const float levels[] = {0.f, -0.f, 0.25f, -0.25f, 0.5f, -0.5f, 1.f, -1.f, 0.75f};
    std::uniform_int_distribution<int> pick(0, 8);
    const float pre = 0.25f;
    long candidates = 0;
    for (int w = 2; w <= 70; ++w)
        for (int trial = 0; trial < 20; ++trial) {
            // Three DoG rows (above, this, below), each from two Gaussian rows.
            std::vector<float> d[2][3], mx[2][3], mn[2][3];
            for (int r = 0; r < 3; ++r) {
                std::vector<float> b(static_cast<size_t>(w)), t(static_cast<size_t>(w));
                for (int i = 0; i < w; ++i) {
                    b[static_cast<size_t>(i)] = levels[pick(rng)];
                    t[static_cast<size_t>(i)] = levels[pick(rng)];
                }
                for (int k = 0; k < 2; ++k) {
                    d[k][r].assign(static_cast<size_t>(w), 9.f);
                    mx[k][r].assign(static_cast<size_t>(w), 9.f);
                    mn[k][r].assign(static_cast<size_t>(w), 9.f);
                }
                sift::dog_row(b.data(), t.data(), d[0][r].data(), mx[0][r].data(), mn[0][r].data(), w);
                sift::dog_row_portable(b.data(), t.data(), d[1][r].data(), mx[1][r].data(), mn[1][r].data(),
                                       w);
                ASSERT_EQ(std::memcmp(d[0][r].data(), d[1][r].data(), sizeof(float) * size_t(w)), 0) << w;
                EXPECT_EQ(mx[0][r][0], 9.f);  // [1, w - 1) only
                for (int i = 1; i < w - 1; ++i) {
                    ASSERT_EQ(mx[0][r][static_cast<size_t>(i)], mx[1][r][static_cast<size_t>(i)])
                        << w << " " << i;
                    ASSERT_EQ(mn[0][r][static_cast<size_t>(i)], mn[1][r][static_cast<size_t>(i)])
                        << w << " " << i;
                }
                EXPECT_EQ(mx[0][r][static_cast<size_t>(w - 1)], 9.f);
            }
            std::vector<int> got(static_cast<size_t>(w) + 16), want(static_cast<size_t>(w) + 16);
            const int n = sift::row_candidates(d[0][1].data(), mx[0][0].data(), mn[0][0].data(),
                                               mx[0][2].data(), mn[0][2].data(), w, pre, got.data());
            const int m =
                sift::row_candidates_portable(d[1][1].data(), mx[1][0].data(), mn[1][0].data(),
                                              mx[1][2].data(), mn[1][2].data(), w, pre, want.data());
            ASSERT_EQ(n, m) << w;
            for (int i = 0; i < n; ++i)
                ASSERT_EQ(got[static_cast<size_t>(i)], want[static_cast<size_t>(i)]) << w;
            candidates += n;
        }
    EXPECT_GT(candidates, 200);  // the rows had candidates to find
}

// Only what is inside the view counts, wherever the object lies in it: the features of an object
// moved by whole pixels move with it (the work is done on the object's box, not the image).
TEST(Sift, FeaturesMoveWithTheObject) {
    const Image img = synthetic(false);
    Image moved(img.size(), 0.f);
    const int dx = 7, dy = -5;
    for (int y = 0; y < kN; ++y)
        for (int x = 0; x < kN; ++x) {
            const int sx = x - dx, sy = y - dy;
            if (sx >= 0 && sy >= 0 && sx < kN && sy < kN)
                moved[static_cast<size_t>(y) * kN + x] = img[static_cast<size_t>(sy) * kN + sx];
        }
    const SiftFeatures a = sift_features(img, kN), b = sift_features(moved, kN);
    // Octave o samples every 2^o-th pixel: a move by (7, -5) is exact at octave 0 (and -1) only.
    std::vector<SiftKeypoint> ka, kb;
    std::vector<Eigen::Index> ra, rb;
    for (size_t i = 0; i < a.keypoints.size(); ++i)
        if (a.keypoints[i].octave <= 0)
            ka.push_back(a.keypoints[i]), ra.push_back(static_cast<Eigen::Index>(i));
    for (size_t i = 0; i < b.keypoints.size(); ++i)
        if (b.keypoints[i].octave <= 0)
            kb.push_back(b.keypoints[i]), rb.push_back(static_cast<Eigen::Index>(i));
    ASSERT_EQ(ka.size(), kb.size());
    ASSERT_GE(ka.size(), 5u);
    for (size_t i = 0; i < ka.size(); ++i) {
        EXPECT_FLOAT_EQ(ka[i].x + dx, kb[i].x);
        EXPECT_FLOAT_EQ(ka[i].y + dy, kb[i].y);
        EXPECT_EQ(ka[i].size, kb[i].size);
        EXPECT_EQ(ka[i].angle, kb[i].angle);
        EXPECT_TRUE(a.descriptors.row(ra[i]) == b.descriptors.row(rb[i]));
    }
}
