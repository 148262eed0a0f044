// SPDX-License-Identifier: GPL-3.0-or-later
#if !defined(__clang__)  // GCC 12 false positive inside Eigen (no such warning in clang)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "canonform/numerics/mds.h"
#include "canonform/numerics/rigid_alignment.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace canonform;
using namespace canonform::numerics;
using Eigen::MatrixXd;

namespace {

MatrixXd random_points(int n, unsigned seed, double half_width = 1.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-half_width, half_width);
    MatrixXd X(n, 3);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) X(i, c) = u(rng);
    return X;
}

MatrixXd sphere_points(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    MatrixXd X(n, 3);
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) X(i, c) = g(rng);
        X.row(i).normalize();
    }
    return X;
}

MatrixXd euclidean_distances(const MatrixXd& P) {
    const Eigen::Index n = P.rows();
    MatrixXd D(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i) D(i, j) = (P.row(i) - P.row(j)).norm();
    return D;
}

/// Great-circle distances between unit vectors (a geodesic, non-Euclidean metric).
MatrixXd great_circle_distances(const MatrixXd& P) {
    const Eigen::Index n = P.rows();
    MatrixXd D(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
            D(i, j) = i == j ? 0.0 : std::acos(std::clamp(P.row(i).dot(P.row(j)), -1.0, 1.0));
    return D;
}

double rms_radius(const MatrixXd& P) {
    const MatrixXd C = P.rowwise() - P.colwise().mean();
    return std::sqrt(C.squaredNorm() / static_cast<double>(P.rows()));
}

/// RMS after the best rigid alignment of X onto P, allowing a reflection (MDS cannot fix it).
double aligned_rms(const MatrixXd& X, const MatrixXd& P) {
    MatrixXd Xr = X;
    Xr.col(0) *= -1;
    return std::min(align_rigid(X, P).rms, align_rigid(Xr, P).rms);
}

/// Dense Torgerson B = -1/2 J D^(2) J.
MatrixXd dense_b(const MatrixXd& D) {
    MatrixXd B = D.array().square().matrix();
    B.rowwise() -= B.colwise().mean();
    B.colwise() -= B.rowwise().mean();
    return -0.5 * B;
}

}  // namespace

TEST(Mds, ClassicalRecoversEuclideanPointSet) {
    const MatrixXd P = random_points(200, 1);
    const MdsResult r = classical_mds(euclidean_distances(P));
    ASSERT_EQ(r.X.rows(), 200);
    ASSERT_EQ(r.X.cols(), 3);
    EXPECT_LT(r.X.colwise().mean().norm(), 1e-12);
    EXPECT_LT(aligned_rms(r.X, P), 1e-6 * rms_radius(P));
    EXPECT_LT(r.final_stress, 1e-16);
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.iterations, 0);
    ASSERT_EQ(r.eigenvalues.size(), 3);
    EXPECT_GE(r.eigenvalues(0), r.eigenvalues(1));
    EXPECT_GE(r.eigenvalues(1), r.eigenvalues(2));
}

TEST(Mds, LandmarkRecoversEuclideanPointSet) {
    const MatrixXd P = random_points(200, 2);
    const MdsResult r = landmark_mds(euclidean_distances(P));
    ASSERT_EQ(r.landmarks.size(), 45u);  // clamp(3 ceil(sqrt(200)), 4, 200)
    EXPECT_LT(r.X.colwise().mean().norm(), 1e-12);
    EXPECT_LT(aligned_rms(r.X, P), 1e-6 * rms_radius(P));
    // Landmarks are distinct and the first one depends on the seed.
    std::vector<int> sorted = r.landmarks;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end());
    MdsOptions opt;
    opt.seed = 12345;
    EXPECT_NE(landmark_mds(euclidean_distances(P), opt).landmarks[0], r.landmarks[0]);
}

TEST(Mds, LandmarkWithFewLandmarksIsStillExactOnEuclideanInput) {
    const MatrixXd P = random_points(200, 3);
    MdsOptions opt;
    opt.landmarks = 4;
    const MdsResult r = landmark_mds(euclidean_distances(P), opt);
    EXPECT_EQ(r.landmarks.size(), 4u);
    EXPECT_LT(aligned_rms(r.X, P), 1e-6 * rms_radius(P));
}

TEST(Mds, LeastSquaresFromRandomStartRecoversEuclideanPointSet) {
    const MatrixXd P = random_points(200, 4);
    const MatrixXd start = random_points(200, 5);
    MdsOptions opt;
    opt.smacof.tolerance = 1e-14;
    opt.smacof.max_iterations = 5000;
    const MdsResult r = least_squares_mds(euclidean_distances(P), opt, &start);
    EXPECT_LT(r.X.colwise().mean().norm(), 1e-12);
    EXPECT_LT(aligned_rms(r.X, P), 1e-4 * rms_radius(P)) << r.iterations << " iterations";
    EXPECT_LT(r.final_stress, 1e-10 * r.initial_stress);
}

TEST(Mds, GuttmanStepEqualsDensePseudoInverseFormula) {
    // One step from X0 must equal V^+ B(X0) X0 with V = N I - 1 1^T (w = 1), computed densely.
    const int n = 20;
    const MatrixXd D = great_circle_distances(sphere_points(n, 6));
    MatrixXd X0 = random_points(n, 7);
    MdsOptions opt;
    opt.smacof.max_iterations = 1;
    opt.smacof.tolerance = 0;
    const MdsResult r = least_squares_mds(D, opt, &X0);
    ASSERT_EQ(r.iterations, 1);
    X0.rowwise() -= X0.colwise().mean();
    MatrixXd B = MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (i != j) B(i, j) = -D(i, j) / (X0.row(i) - X0.row(j)).norm();
    for (int i = 0; i < n; ++i) B(i, i) = -B.row(i).sum();
    const MatrixXd V = n * MatrixXd::Identity(n, n) - MatrixXd::Ones(n, n);
    const MatrixXd Vpinv = V.completeOrthogonalDecomposition().pseudoInverse();
    const MatrixXd X1 = Vpinv * B * X0;
    EXPECT_LT((r.X - X1).norm(), 1e-12 * X1.norm());
    EXPECT_NEAR(r.initial_stress, raw_stress(D, X0), 1e-12 * r.initial_stress);
    EXPECT_NEAR(r.final_stress, raw_stress(D, r.X), 1e-12 * r.final_stress);
}

TEST(Mds, LeastSquaresStressNeverIncreasesOnGeodesicDistances) {
    const MatrixXd D = great_circle_distances(sphere_points(300, 8));
    const MdsResult c = classical_mds(D);
    MdsOptions opt;
    opt.smacof.tolerance = 0;
    opt.smacof.max_iterations = 150;
    opt.smacof.record_history = true;
    opt.smacof.acceleration = SmacofAcceleration::None;  // plain Guttman steps (accelerations: below)
    const MdsResult r = least_squares_mds(D, opt);
    // With tolerance 0 it runs until the stress stops decreasing in floating point (~50 steps).
    ASSERT_EQ(r.stress_history.size(), static_cast<size_t>(r.iterations) + 1);
    EXPECT_GE(r.iterations, 20);
    EXPECT_NEAR(r.stress_history.front(), c.final_stress, 1e-9 * c.final_stress);  // starts from classical
    for (size_t k = 1; k < r.stress_history.size(); ++k)
        EXPECT_LE(r.stress_history[k], r.stress_history[k - 1] * (1 + 1e-12)) << "iteration " << k;
    EXPECT_LT(r.final_stress, 0.9 * c.final_stress);
    EXPECT_NEAR(r.final_stress, raw_stress(D, r.X), 1e-9 * r.final_stress);
    EXPECT_EQ(r.converged, r.iterations < 150);

    // With the default tolerance it stops by itself, below classical MDS's stress.
    const MdsResult d = mds(D, MdsMethod::LeastSquares);
    EXPECT_TRUE(d.converged);
    EXPECT_LT(d.iterations, 500);
    EXPECT_LT(d.final_stress, 0.9 * c.final_stress);
}

TEST(Mds, LeastSquaresWithEveryAccelerationNeverRaisesTheStressAndReachesThePlainStress) {
    const MatrixXd D = great_circle_distances(sphere_points(300, 8));
    MdsOptions opt;
    opt.smacof.acceleration = SmacofAcceleration::None;
    const MdsResult plain = least_squares_mds(D, opt);
    for (SmacofAcceleration a : {SmacofAcceleration::Relaxed, SmacofAcceleration::Rre,
                                 SmacofAcceleration::Mpe, SmacofAcceleration::Anderson}) {
        SCOPED_TRACE(to_string(a));
        opt.smacof.acceleration = a;
        opt.smacof.record_history = true;
        const MdsResult r = least_squares_mds(D, opt);
        for (size_t k = 1; k < r.stress_history.size(); ++k)
            ASSERT_LE(r.stress_history[k], r.stress_history[k - 1] * (1 + 1e-12)) << "iterate " << k;
        EXPECT_TRUE(r.converged);
        EXPECT_LE(r.final_stress, plain.final_stress * 1.002);
        EXPECT_NEAR(r.final_stress, raw_stress(D, r.X), 1e-9 * r.final_stress);
    }
}

TEST(Mds, ClassicalOnSphereGeodesicsIsRoughlyASphere) {
    const MatrixXd P = sphere_points(300, 9);
    const MatrixXd D = great_circle_distances(P);
    const MdsResult r = classical_mds(D);
    // A scaled copy of the sampled sphere (up to an isometry).
    MatrixXd Xr = r.X;
    Xr.col(0) *= -1;
    EXPECT_LT(std::min(align_rigid(r.X, P, true).rms, align_rigid(Xr, P, true).rms), 0.05);
    const Eigen::VectorXd radius = r.X.rowwise().norm();
    const double mean = radius.mean();
    const double spread = std::sqrt((radius.array() - mean).square().mean());
    EXPECT_GT(mean, 0.5);
    EXPECT_LT(spread, 0.05 * mean);
    // The three eigenvalues of a round sphere are nearly equal.
    EXPECT_LT(r.eigenvalues(0) / r.eigenvalues(2), 1.3);
}

TEST(Mds, ClassicalEigenpairsMatchDenseEigensolver) {
    const MatrixXd D = great_circle_distances(sphere_points(300, 10));
    const MdsResult r = classical_mds(D);
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(dense_b(D));
    const Eigen::VectorXd top = es.eigenvalues().reverse().head(3);
    EXPECT_LT((r.eigenvalues - top).norm(), 1e-8 * top(0));
    // Same subspace: the configuration matches the dense one up to an isometry.
    MatrixXd Xd = es.eigenvectors().rowwise().reverse().leftCols(3) * top.cwiseSqrt().asDiagonal();
    EXPECT_LT(aligned_rms(r.X, Xd), 1e-6 * rms_radius(Xd));
}

TEST(Mds, LandmarkWithAllPointsAsLandmarksEqualsClassical) {
    const MatrixXd D = great_circle_distances(sphere_points(150, 11));
    MdsOptions opt;
    opt.landmarks = 150;
    const MdsResult l = landmark_mds(D, opt);
    const MdsResult c = classical_mds(D);
    EXPECT_LT(aligned_rms(l.X, c.X), 1e-6 * rms_radius(c.X));
    EXPECT_NEAR(l.final_stress, c.final_stress, 1e-6 * c.final_stress);
    // Default landmarks: a reasonable approximation on this non-Euclidean D.
    const MdsResult d = landmark_mds(D);
    EXPECT_LT(d.final_stress, 1.2 * c.final_stress);
}

TEST(Mds, PlanarInputGivesAZeroThirdCoordinate) {
    MatrixXd P = random_points(120, 12);
    P.col(2).setZero();
    const MatrixXd D = euclidean_distances(P);
    const MdsResult c = classical_mds(D);
    EXPECT_LT(c.X.col(2).norm(), 1e-6 * c.X.norm());
    EXPECT_LT(aligned_rms(c.X, P), 1e-6 * rms_radius(P));
    const MdsResult l = landmark_mds(D);
    EXPECT_LT(aligned_rms(l.X, P), 1e-6 * rms_radius(P));
    // SMACOF from the (rank-2) classical start: the degenerate column gets a tiny seeded fill.
    const MdsResult s = least_squares_mds(D);
    EXPECT_TRUE(s.X.allFinite());
    EXPECT_LT(s.final_stress, 1e-8 * D.squaredNorm());
}

TEST(Mds, TwoDimensionalEmbeddingsOfPlanarPoints) {
    MatrixXd P = random_points(150, 18);
    P.col(2).setZero();
    const MatrixXd D = euclidean_distances(P);
    MdsOptions opt;
    opt.dim = 2;
    const auto pad = [](const MatrixXd& X2) {
        MatrixXd X3 = MatrixXd::Zero(X2.rows(), 3);
        X3.leftCols(2) = X2;
        return X3;
    };
    const MdsResult c = classical_mds(D, opt);
    ASSERT_EQ(c.X.cols(), 2);
    EXPECT_LT(aligned_rms(pad(c.X), P), 1e-6 * rms_radius(P));
    const MdsResult l = landmark_mds(D, opt);
    EXPECT_LT(aligned_rms(pad(l.X), P), 1e-6 * rms_radius(P));
    opt.smacof.tolerance = 1e-14;
    opt.smacof.max_iterations = 5000;
    const MatrixXd start = random_points(150, 19).leftCols(2);
    const MdsResult s = least_squares_mds(D, opt, &start);
    EXPECT_LT(aligned_rms(pad(s.X), P), 1e-4 * rms_radius(P));
}

TEST(Mds, CoincidentPointsAreHandled) {
    // Duplicated points: d_ij = 0 in every configuration, where b_ij must be 0 (not 0/0).
    MatrixXd P = random_points(100, 20);
    P.middleRows(50, 10) = P.topRows(10);
    const MatrixXd D = euclidean_distances(P);
    for (MdsMethod m : {MdsMethod::LeastSquares, MdsMethod::Classical, MdsMethod::Landmark}) {
        const MdsResult r = mds(D, m);
        ASSERT_TRUE(r.X.allFinite()) << static_cast<int>(m);
        EXPECT_LT(aligned_rms(r.X, P), 1e-6 * rms_radius(P)) << static_cast<int>(m);
    }
}

TEST(Mds, EigensolverFindsPositiveEigenvaluesBehindLargeNegativeOnes) {
    // Spectrum 10, -9, ..., -4 dominates in magnitude; the wanted 3rd-largest is 3.
    const int n = 60;
    Eigen::VectorXd spectrum = Eigen::VectorXd::Zero(n);
    const double values[] = {10, -9, -8, -7, -6, -5, -4, 3, 2, 1, 0.5};
    for (int k = 0; k < 11; ++k) spectrum(k) = values[k];
    std::mt19937 rng(13);
    std::normal_distribution<double> g;
    MatrixXd R(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) R(i, j) = g(rng);
    const MatrixXd Qr = Eigen::HouseholderQR<MatrixXd>(R).householderQ();
    const MatrixXd B = Qr * spectrum.asDiagonal() * Qr.transpose();
    const numerics::detail::EigenPairs e = numerics::detail::top_eigenpairs(
        n, 3, [&B](const MatrixXd& Q) { return MatrixXd(B * Q); }, 1e-10, 5000, 1);
    EXPECT_TRUE(e.shifted);
    EXPECT_NEAR(e.values(0), 10, 1e-8);
    EXPECT_NEAR(e.values(1), 3, 1e-8);
    EXPECT_NEAR(e.values(2), 2, 1e-8);
    EXPECT_LT((B * e.vectors - e.vectors * e.values.asDiagonal()).norm(), 1e-7);
    // Too few iterations: NumericalError.
    EXPECT_THROW(numerics::detail::top_eigenpairs(
                     n, 3, [&B](const MatrixXd& Q) { return MatrixXd(B * Q); }, 1e-10, 5, 1),
                 NumericalError);
}

TEST(Mds, ThreadCountDoesNotChangeTheResult) {
    const MatrixXd D = great_circle_distances(sphere_points(700, 14));
    MdsOptions one, two;
    one.threads = 1;
    two.threads = 2;
    one.smacof.tolerance = two.smacof.tolerance = 0;
    one.smacof.max_iterations = two.smacof.max_iterations = 30;
    // The same bits: users' machines differ in their number of cores.
    const MdsResult a = least_squares_mds(D, one), b = least_squares_mds(D, two);
    EXPECT_TRUE((a.X.array() == b.X.array()).all());
    EXPECT_EQ(a.final_stress, b.final_stress);
    EXPECT_EQ(raw_stress(D, a.X, 1), raw_stress(D, a.X, 2));
    MdsOptions three = two;
    three.threads = 3;
    EXPECT_TRUE((least_squares_mds(D, three).X.array() == a.X.array()).all());
    const MdsResult c1 = classical_mds(D, one), c2 = classical_mds(D, two), c3 = classical_mds(D, three);
    EXPECT_TRUE((c1.X.array() == c2.X.array()).all());
    EXPECT_TRUE((c1.X.array() == c3.X.array()).all());
}

TEST(Mds, BadInputThrowsInputError) {
    const MatrixXd D = euclidean_distances(random_points(20, 15));
    const MdsMethod methods[] = {MdsMethod::LeastSquares, MdsMethod::Classical, MdsMethod::Landmark};
    for (MdsMethod m : methods) {
        SCOPED_TRACE(static_cast<int>(m));
        MatrixXd A = D;
        A(3, 7) += 0.1;  // asymmetric
        EXPECT_THROW(mds(A, m), InputError);
        A = D;
        A(4, 9) = A(9, 4) = std::numeric_limits<double>::quiet_NaN();
        EXPECT_THROW(mds(A, m), InputError);
        A = D;
        A(4, 9) = A(9, 4) = std::numeric_limits<double>::infinity();
        EXPECT_THROW(mds(A, m), InputError);
        A = D;
        A(2, 5) = A(5, 2) = -1.0;
        EXPECT_THROW(mds(A, m), InputError);
        A = D;
        A(6, 6) = 0.5;  // non-zero diagonal
        EXPECT_THROW(mds(A, m), InputError);
        EXPECT_THROW(mds(D.leftCols(19), m), InputError);         // not square
        EXPECT_THROW(mds(MatrixXd(), m), InputError);             // empty
        EXPECT_THROW(mds(D.topLeftCorner(3, 3), m), InputError);  // 3 points cannot span 3D
        MdsOptions zero_dim;
        zero_dim.dim = 0;
        EXPECT_THROW(mds(D, m, zero_dim), InputError);
        EXPECT_NO_THROW(mds(D, m));
    }
    // The message names the problem.
    MatrixXd A = D;
    A(3, 7) += 0.1;
    try {
        classical_mds(A);
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not symmetric"), std::string::npos) << e.what();
    }
    // Bad start and landmark counts.
    const MatrixXd bad_start = MatrixXd::Zero(20, 2);
    EXPECT_THROW(least_squares_mds(D, {}, &bad_start), InputError);
    MatrixXd nan_start = MatrixXd::Zero(20, 3);
    nan_start(1, 1) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(least_squares_mds(D, {}, &nan_start), InputError);
    MdsOptions few;
    few.landmarks = 3;
    EXPECT_THROW(landmark_mds(D, few), InputError);
    few.landmarks = 21;
    EXPECT_THROW(landmark_mds(D, few), InputError);
    EXPECT_THROW(raw_stress(D, MatrixXd::Zero(19, 3)), InputError);
}

TEST(Mds, ProgressCanCancel) {
    const MatrixXd D = great_circle_distances(sphere_points(200, 16));
    MdsOptions opt;
    opt.smacof.tolerance = 0;
    opt.smacof.max_iterations = 100;
    int calls = 0;
    opt.progress = [&calls](double f, const char*) {
        EXPECT_GE(f, 0.0);
        EXPECT_LE(f, 1.0);
        return ++calls < 3;
    };
    EXPECT_THROW(least_squares_mds(D, opt), Cancelled);
    EXPECT_EQ(calls, 3);
}

TEST(Mds, TimingsAtN2000) {
    const MatrixXd D = great_circle_distances(sphere_points(2000, 17));
    using clock = std::chrono::steady_clock;
    const auto seconds = [](clock::time_point a) {
        return std::chrono::duration<double>(clock::now() - a).count();
    };
    auto t0 = clock::now();
    const MdsResult c = classical_mds(D);
    const double tc = seconds(t0);
    t0 = clock::now();
    const MdsResult l = landmark_mds(D);
    const double tl = seconds(t0);
    t0 = clock::now();
    const MdsResult s = least_squares_mds(D);
    const double ts = seconds(t0);
    std::printf(
        "[ timing ] N = 2000 (sphere geodesics): classical %.3f s (%d subspace iterations, stress %.4g), "
        "landmark %.3f s (%zu landmarks, stress %.4g), least squares %.3f s (%d iterations, stress %.4g)\n",
        tc, c.iterations, c.final_stress, tl, l.landmarks.size(), l.final_stress, ts, s.iterations,
        s.final_stress);
    EXPECT_LT(s.final_stress, c.final_stress);
}

TEST(Mds, SameBitsWhateverTheCpuCacheSizes) {
    // Eigen blocks a matrix product by the cache sizes that CPUID reports; none of the three MDS
    // depends on them (their products with a long inner dimension are summed in fixed blocks).
    const MatrixXd D = great_circle_distances(sphere_points(700, 9));
    MdsOptions o;
    o.threads = 1;
    o.smacof.max_iterations = 20;
    o.landmarks = 300;  // a landmark block longer than Eigen's product blocks
    for (MdsMethod m : {MdsMethod::Classical, MdsMethod::Landmark, MdsMethod::LeastSquares}) {
        const auto runs = canonform::test::under_l1_cache_sizes([&] { return mds(D, m, o).X; });
        for (const MatrixXd& X : runs)
            EXPECT_TRUE((X.array() == runs[0].array()).all()) << static_cast<int>(m);
    }
}
