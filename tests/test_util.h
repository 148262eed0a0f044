// SPDX-License-Identifier: GPL-3.0-or-later
// Shared helpers of the core tests: small hand-made meshes and comparisons.
#pragma once

#include "canonform/procedural/procedural_meshes.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
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
    for (const auto& c : {std::array<std::ptrdiff_t, 3>{16 * K, 256 * K, 2048 * K}, {32 * K, 512 * K, 8192 * K},
                          {48 * K, 1280 * K, 30720 * K}, {64 * K, 512 * K, 16384 * K}}) {
        Eigen::setCpuCacheSizes(c[0], c[1], c[2]);
        out.push_back(fn());
    }
    Eigen::setCpuCacheSizes(l1, l2, l3);
    return out;
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

/// A fresh, empty folder under the temporary directory ("canonform_test_NAME").
std::string scratch_dir(const std::string& name);

/// The what() of the exception fn() throws ("" if none).
std::string message_of(const std::function<void()>& fn);

/// Writes `bytes` as the seed NAME of fuzz target TARGET (tests/fuzz) when the environment
/// variable CANONFORM_FUZZ_SEEDS names a folder (the fuzz build's ctest sets it): the fuzz corpora
/// start from the files the tests build, valid and broken.
void fuzz_seed(const std::string& target, const std::string& name, const std::string& bytes);

}  // namespace canonform::test
