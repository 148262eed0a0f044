// SPDX-License-Identifier: GPL-3.0-or-later
// Shared helpers of the core tests: small hand-made meshes and comparisons.
#pragma once

#include "canonform/procedural/procedural_meshes.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace canonform::test {

/// The results of fn() with Eigen's matrix products blocked as on CPUs with L1 / L2 / L3 caches of
/// 16 KiB / 256 KiB / 2 MiB, 32 KiB / 512 KiB / 8 MiB, 48 KiB / 1.25 MiB / 30 MiB and
/// 64 KiB / 512 KiB / 16 MiB (qemu64) (Eigen reads the cache sizes from CPUID at run time and
/// splits the inner dimension of a product into blocks sized from L1, so the rounding of a product
/// can depend on the CPU). The cache sizes in force before are restored.
template <typename Fn>
auto under_l1_cache_sizes(Fn fn) -> std::vector<decltype(fn())> {
    const std::ptrdiff_t l1 = Eigen::l1CacheSize(), l2 = Eigen::l2CacheSize(), l3 = Eigen::l3CacheSize();
    std::vector<decltype(fn())> out;
    const std::ptrdiff_t K = 1024;
    for (const auto& c : {std::array<std::ptrdiff_t, 3>{16 * K, 256 * K, 2048 * K},
                          {32 * K, 512 * K, 8192 * K},
                          {48 * K, 1280 * K, 30720 * K},
                          {64 * K, 512 * K, 16384 * K}}) {
        Eigen::setCpuCacheSizes(c[0], c[1], c[2]);
        out.push_back(fn());
    }
    Eigen::setCpuCacheSizes(l1, l2, l3);
    return out;
}

/// The height of the synthetic depth scene the SIFT tests view, at (x, y) in [-1, 1]^2 (x right,
/// y down), or -2 off the scene: a sphere of radius 0.8 with nine Gaussian bumps (bumps = true),
/// or a capsule stick figure.
inline double synthetic_scene_height(bool bumps, double x, double y) {
    double z = -2;
    if (bumps) {
        const double q = 0.64 - x * x - y * y;
        if (q > 0) {
            z = std::sqrt(q);
            for (int k = 0; k < 9; ++k) {
                const double bx = -0.45 + 0.45 * (k % 3), by = -0.45 + 0.45 * (k / 3);
                z += 0.15 * std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / 0.01);
            }
        }
        return z;
    }
    const auto cap = [&](double ax, double ay, double bx, double by, double rad, double base) {
        const double dx = bx - ax, dy = by - ay;
        const double t = std::clamp(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
        const double px = ax + t * dx - x, py = ay + t * dy - y, q = rad * rad - px * px - py * py;
        if (q > 0) z = std::max(z, base + std::sqrt(q));
    };
    cap(0, -0.35, 0, 0.2, 0.17, 0);
    cap(0, -0.62, 0, -0.6, 0.12, 0.02);
    cap(-0.12, -0.3, -0.6, -0.05, 0.06, 0.05);
    cap(0.12, -0.3, 0.55, -0.55, 0.06, 0.05);
    cap(-0.08, 0.2, -0.3, 0.9, 0.08, 0);
    cap(0.08, 0.2, 0.25, 0.9, 0.08, -0.05);
    return z;
}

/// A random rotation (uniform from a seeded quaternion).
inline Eigen::Matrix3d random_rotation(unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    return q.toRotationMatrix();
}

/// The rows of V permuted by a seeded random permutation; perm[k] = old index of new row k.
inline Eigen::VectorXi random_permutation(Eigen::Index n, unsigned seed) {
    Eigen::VectorXi p = Eigen::VectorXi::LinSpaced(n, 0, static_cast<int>(n) - 1);
    std::mt19937 rng(seed);
    std::shuffle(p.data(), p.data() + n, rng);
    return p;
}

/// Applies a vertex permutation to (V, F): new vertex k is old vertex perm[k].
inline void permute_mesh(const Eigen::VectorXi& perm, Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
    Eigen::VectorXi inv(perm.size());
    for (Eigen::Index k = 0; k < perm.size(); ++k) inv(perm(k)) = static_cast<int>(k);
    Eigen::MatrixXd V2(V.rows(), 3);
    for (Eigen::Index k = 0; k < perm.size(); ++k) V2.row(k) = V.row(perm(k));
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        for (int c = 0; c < 3; ++c) F(f, c) = inv(F(f, c));
    V = V2;
}

/// RMS distance between two configurations after the best rigid alignment, relative to the
/// RMS radius of `b`.
double aligned_rms(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

/// The same, also allowing a reflection (MDS determines a configuration only up to one).
double aligned_rms_or_mirrored(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

/// The path NAME_PID under the temporary directory: this process's own (ctest runs the tests in
/// parallel processes, and other checkouts' tests may run on the same machine). Nothing is made
/// there; whatever is, and whatever is beside it named NAME_PID_..., is removed when the test
/// program ends.
std::string process_temp_path(const std::string& name);

/// A fresh, empty folder of this process under the temporary directory
/// (process_temp_path("canonform_test_NAME"), removed when the test program ends).
std::string scratch_dir(const std::string& name);

/// The what() of the exception fn() throws ("" if none).
std::string message_of(const std::function<void()>& fn);

/// Writes `bytes` as the seed NAME of fuzz target TARGET (tests/fuzz) when the environment
/// variable CANONFORM_FUZZ_SEEDS names a folder (the fuzz build's ctest sets it): the fuzz corpora
/// start from the files the tests build, valid and broken.
void fuzz_seed(const std::string& target, const std::string& name, const std::string& bytes);

}  // namespace canonform::test
