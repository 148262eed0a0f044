// SPDX-License-Identifier: GPL-3.0-or-later
// numerics/portable_math.h: accuracy against glibc's libm, special values, the law of the normal
// draws, and the SIFT's 4-lane angle (views/sift_simd.h) equal to the scalar one.
#include "canonform/numerics/portable_math.h"
#include "canonform/views/sift_simd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace cf = canonform;
using cf::numerics::portable_atan2;
using cf::numerics::portable_exp;
using cf::numerics::portable_exp2;
using cf::numerics::portable_log;
using cf::numerics::portable_sincos;

namespace {
const double kInf = std::numeric_limits<double>::infinity();
}

TEST(PortableMath, ExpWithinAUnitInTheLastPlaceOfLibm) {
    // Arguments uniform over the range of normal results, and near 0 (ldexp is exact, so the
    // arguments are the same on every CPU).
    std::mt19937_64 g(11);
    std::uniform_real_distribution<double> u(-708.0, 709.7);
    double max_rel = 0;
    for (int i = 0; i < 200000; ++i) {
        const double x = i % 2 ? u(g) : std::ldexp(u(g) / 709.0, -static_cast<int>(g() % 40));
        const double a = portable_exp(x), b = std::exp(x);
        max_rel = std::max(max_rel, std::abs(a - b) / b);
    }
    EXPECT_LE(max_rel, 2.5e-16);
    // Subnormal results (gradual underflow, absolute accuracy), overflow.
    for (double x : {-709.0, -720.0, -740.0, -745.0})
        EXPECT_NEAR(portable_exp(x), std::exp(x), 2 * std::numeric_limits<double>::denorm_min()) << x;
    EXPECT_NEAR(portable_exp(709.78) / std::exp(709.78), 1.0, 2.5e-16);
}

TEST(PortableMath, Exp2WithinTheRoundingOfItsArgument) {
    std::mt19937_64 g(12);
    std::uniform_real_distribution<double> u(-6.0, 6.0);
    double max_rel = 0;
    for (int i = 0; i < 100000; ++i) {
        const double x = u(g);
        max_rel = std::max(max_rel, std::abs(portable_exp2(x) - std::exp2(x)) / std::exp2(x));
    }
    EXPECT_LE(max_rel, 7e-16);
    // 2^n for whole n: exact in libm, here within the rounding of n ln2 (|n| ln2 1.1e-16 relative).
    for (int n = -20; n <= 20; ++n)
        EXPECT_NEAR(portable_exp2(n), std::ldexp(1.0, n),
                    (2.5e-16 + 0.77e-16 * std::abs(n)) * std::ldexp(1.0, n))
            << n;
}

TEST(PortableMath, ExpSpecialValues) {
    EXPECT_EQ(portable_exp(0.0), 1.0);
    EXPECT_EQ(portable_exp(-0.0), 1.0);
    EXPECT_EQ(portable_exp(-746.0), 0.0);
    EXPECT_EQ(portable_exp(-kInf), 0.0);
    EXPECT_EQ(portable_exp(710.0), kInf);
    EXPECT_EQ(portable_exp(kInf), kInf);
    EXPECT_TRUE(std::isnan(portable_exp(std::nan(""))));
    EXPECT_EQ(portable_exp2(0.0), 1.0);
}

TEST(PortableMath, SinCosWithinAUnitInTheLastPlaceOfLibm) {
    std::mt19937_64 g(13);
    for (double range : {7.0, 1e4}) {
        std::uniform_real_distribution<double> u(-range, range);
        double max_abs = 0;
        for (int i = 0; i < 100000; ++i) {
            const double a = u(g);
            double s, c;
            portable_sincos(a, s, c);
            max_abs = std::max({max_abs, std::abs(s - std::sin(a)), std::abs(c - std::cos(a))});
        }
        EXPECT_LE(max_abs, 3.4e-16) << range;
    }
    // Up to 1e6 the reduction loses a little (see the header).
    std::uniform_real_distribution<double> big(-1e6, 1e6);
    for (int i = 0; i < 10000; ++i) {
        const double a = big(g);
        double s, c;
        portable_sincos(a, s, c);
        ASSERT_NEAR(s, std::sin(a), 1e-13) << a;
        ASSERT_NEAR(c, std::cos(a), 1e-13) << a;
    }
}

TEST(PortableMath, SinCosSpecialValues) {
    double s, c;
    portable_sincos(0.0, s, c);
    EXPECT_EQ(s, 0.0);
    EXPECT_EQ(c, 1.0);
    portable_sincos(M_PI / 2, s, c);
    EXPECT_NEAR(s, 1.0, 1.2e-16);
    EXPECT_NEAR(c, 0.0, 3.4e-16);
    for (double bad : {kInf, -kInf, std::nan(""), 1.5e6}) {
        portable_sincos(bad, s, c);
        EXPECT_TRUE(std::isnan(s) && std::isnan(c)) << bad;
    }
}

TEST(PortableMath, Atan2WithinAFewUnitsInTheLastPlaceOfLibm) {
    // Arguments over 40 binary orders of magnitude and every octant.
    std::mt19937_64 g(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double max_abs = 0, max_rel = 0;
    for (int i = 0; i < 200000; ++i) {
        const double y = std::ldexp(u(g), static_cast<int>(g() % 40) - 20);
        const double x = std::ldexp(u(g), static_cast<int>(g() % 40) - 20);
        const double a = portable_atan2(y, x), b = std::atan2(y, x);
        max_abs = std::max(max_abs, std::abs(a - b));
        max_rel = std::max(max_rel, std::abs(a - b) / std::abs(b));
        ASSERT_LE(std::abs(a), M_PI);
        ASSERT_EQ(std::signbit(a), std::signbit(y)) << y << " " << x;
    }
    EXPECT_LE(max_abs, 4.5e-16);
    EXPECT_LE(max_rel, 1.2e-15);
    // Octant boundaries and the switch of the reduction at tan(pi/8).
    for (double t : {0.0, 1e-300, 1e-8, 0.41421356237309503, 0.41421356237309515, 0.5, 1.0, 2.0, 1e8}) {
        for (double sx : {1.0, -1.0})
            for (double sy : {1.0, -1.0})
                EXPECT_NEAR(portable_atan2(sy * t, sx * 1.0), std::atan2(sy * t, sx * 1.0), 4.5e-16) << t;
    }
}

TEST(PortableMath, Atan2SpecialValuesAsInC) {
    EXPECT_EQ(portable_atan2(0.0, 1.0), 0.0);
    EXPECT_TRUE(std::signbit(portable_atan2(-0.0, 1.0)));
    EXPECT_EQ(portable_atan2(0.0, 0.0), 0.0);
    EXPECT_EQ(portable_atan2(0.0, -0.0), M_PI);
    EXPECT_EQ(portable_atan2(-0.0, -1.0), -M_PI);
    EXPECT_EQ(portable_atan2(1.0, 0.0), M_PI / 2);
    EXPECT_EQ(portable_atan2(-1.0, -0.0), -M_PI / 2);
    EXPECT_EQ(portable_atan2(1.0, 1.0), M_PI / 4);
    EXPECT_EQ(portable_atan2(1.0, kInf), 0.0);
    EXPECT_EQ(portable_atan2(kInf, 1.0), M_PI / 2);
    EXPECT_NEAR(portable_atan2(kInf, -kInf), 3 * M_PI / 4, 4.5e-16);
    EXPECT_TRUE(std::isnan(portable_atan2(std::nan(""), 1.0)));
    EXPECT_TRUE(std::isnan(portable_atan2(1.0, std::nan(""))));
}

TEST(PortableMath, Atan2ManyAtOnceEqualsTheScalar) {
    // The batched portable_atan2 (four lanes at a time where no special value is among them) gives
    // each angle's bits as the scalar does: random points at every scale and in every quadrant,
    // both range reductions, and blocks holding special values (zeros of both signs, infinities,
    // NaN, subnormals), with a count that leaves a remainder of the four.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> e(-40, 40);
    std::vector<double> y, x;
    for (int k = 0; k < 4001; ++k) {
        y.push_back(std::ldexp(u(rng), e(rng)));
        x.push_back(std::ldexp(u(rng), e(rng)));
    }
    const double special[] = {0.0,
                              -0.0,
                              kInf,
                              -kInf,
                              std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::denorm_min(),
                              -1e-310,
                              1.0,
                              -1.0};
    for (const double a : special)
        for (const double b : special) {
            y.push_back(a);
            x.push_back(b);
        }
    std::vector<double> out(y.size());
    portable_atan2(y.data(), x.data(), out.data(), y.size());
    int different = 0;
    for (size_t k = 0; k < y.size(); ++k) {
        const double one = portable_atan2(y[k], x[k]);
        if (std::memcmp(&one, &out[k], sizeof one) != 0) ++different;
    }
    EXPECT_EQ(different, 0) << "of " << y.size();
}

TEST(PortableMath, ExpManyAtOnceEqualsTheScalar) {
    // The batched portable_exp (four lanes at a time where no special value is among them) gives
    // each value's bits as the scalar does: arguments over the whole range, the SIFT windows'
    // small negative ones, and blocks holding special values (NaN, infinities, the ends of the
    // range where the scale is taken in two steps), with a count that leaves a remainder of four.
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> wide(-750, 712), window(-20, 0);
    std::vector<double> x;
    for (int k = 0; k < 3001; ++k) x.push_back(k % 2 ? wide(rng) : window(rng));
    const double special[] = {0.0,    -0.0,   kInf,   -kInf,  std::numeric_limits<double>::quiet_NaN(),
                              709.78, 709.8,  -708.5, -745.1, -745.3,
                              1e-300, -1e-310};
    for (const double a : special) {
        x.push_back(a);
        for (int k = 0; k < 3; ++k) x.push_back(window(rng));
    }
    x.push_back(-1.5);
    std::vector<double> out(x.size());
    portable_exp(x.data(), out.data(), x.size());
    int different = 0;
    for (size_t k = 0; k < x.size(); ++k) {
        const double one = portable_exp(x[k]);
        if (std::memcmp(&one, &out[k], sizeof one) != 0) ++different;
    }
    EXPECT_EQ(different, 0) << "of " << x.size();
}

TEST(PortableMath, ApproximateAngleWithinItsBoundAndRange) {
    std::mt19937_64 g(17);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    double max_err = 0;
    for (int i = 0; i < 200000; ++i) {
        const float y = std::ldexp(u(g), static_cast<int>(g() % 16) - 8),
                    x = std::ldexp(u(g), static_cast<int>(g() % 16) - 8);
        const float a = cf::numerics::approximate_angle_0_to_2pi(y, x);
        ASSERT_GE(a, 0.f);
        ASSERT_LE(a, 6.28318548f);
        double ref = std::atan2(double(y), double(x));
        if (ref < 0) ref += 2 * M_PI;
        double err = std::abs(double(a) - ref);
        err = std::min(err, std::abs(err - 2 * M_PI));  // 2 pi and 0 are the same angle
        max_err = std::max(max_err, err);
    }
    EXPECT_LE(max_err, 1.2e-5);
    EXPECT_EQ(cf::numerics::approximate_angle_0_to_2pi(0.f, 0.f), 0.f);
    EXPECT_EQ(cf::numerics::approximate_angle_0_to_2pi(0.f, 1.f), 0.f);
    EXPECT_NEAR(cf::numerics::approximate_angle_0_to_2pi(1.f, 0.f), M_PI / 2, 1e-6);
    EXPECT_NEAR(cf::numerics::approximate_angle_0_to_2pi(0.f, -1.f), M_PI, 1e-6);
    EXPECT_NEAR(cf::numerics::approximate_angle_0_to_2pi(-1.f, 0.f), 3 * M_PI / 2, 1e-6);
}

TEST(PortableMath, ApproximateAngleEightLanesEqualTheScalar) {
    // The SIFT windows' angles, eight samples at a time (views/sift_simd.h).
    std::mt19937_64 g(19);
    std::uniform_int_distribution<int> level(-255, 255);  // central differences of 8-bit views
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int i = 0; i < 50000; ++i) {
        float y[8], x[8];
        for (int q = 0; q < 8; ++q) {
            y[q] = i % 2 ? level(g) / 255.f : u(g);
            x[q] = i % 2 ? level(g) / 255.f : u(g);
            if (y[q] == 0.f && x[q] == 0.f) x[q] = 1.f / 255.f;  // (the lanes' precondition)
        }
        namespace s = cf::views::sift;
        float a[8];
        s::store8(a, s::approximate_angle_0_to_2pi_lanes(s::load8(y), s::load8(x)));
        for (int q = 0; q < 8; ++q) {
            const float b = cf::numerics::approximate_angle_0_to_2pi(y[q], x[q]);
            ASSERT_EQ(std::memcmp(&a[q], &b, sizeof b), 0) << y[q] << " " << x[q];
        }
    }
}

TEST(PortableMath, LogWithinAUnitInTheLastPlaceOfLibm) {
    std::mt19937_64 g(20);
    int worst = 0;
    for (int i = 0; i < 200000; ++i) {
        // mantissas in [1, 2) over 600 binary orders of magnitude (ldexp is exact), and values near 1
        const double m = 1.0 + static_cast<double>(g() >> 11) * 0x1.0p-53;
        const double x =
            i % 4 == 0 ? 1.0 + (m - 1.5) * 1e-6 : std::ldexp(m, static_cast<int>(g() % 600) - 300);
        const double a = portable_log(x), b = std::log(x);
        const double ulp = std::nextafter(std::abs(b), kInf) - std::abs(b);
        const int units = static_cast<int>(std::round(std::abs(a - b) / ulp));
        worst = std::max(worst, units);
        ASSERT_LE(units, 1) << x;
    }
    std::printf("[portable_log] at most %d units in the last place from std::log\n", worst);
}

TEST(PortableMath, LogSpecialValues) {
    EXPECT_EQ(portable_log(1.0), 0.0);
    EXPECT_DOUBLE_EQ(portable_log(std::ldexp(1.0, 10)), 10 * std::log(2.0));
    EXPECT_EQ(portable_log(0.0), -kInf);
    EXPECT_EQ(portable_log(-0.0), -kInf);
    EXPECT_TRUE(std::isnan(portable_log(-1.0)));
    EXPECT_TRUE(std::isnan(portable_log(-kInf)));
    EXPECT_TRUE(std::isnan(portable_log(std::numeric_limits<double>::quiet_NaN())));
    EXPECT_EQ(portable_log(kInf), kInf);
    EXPECT_NEAR(portable_log(std::numeric_limits<double>::denorm_min()), -744.44007192138127, 1e-12);
}

TEST(PortableMath, StandardNormalDrawsSeededAndOfTheRightLaw) {
    std::mt19937_64 a(3), b(3), c(4);
    cf::numerics::StandardNormalDraws na, nb, nc;
    const int n = 400000;
    double sum = 0, sum2 = 0, sum4 = 0;
    int within1 = 0, same_as_other_seed = 0;
    for (int i = 0; i < n; ++i) {
        const double x = na(a);
        ASSERT_EQ(x, nb(b));  // a seed gives the same numbers
        ASSERT_TRUE(std::isfinite(x));
        same_as_other_seed += x == nc(c);
        sum += x;
        sum2 += x * x;
        sum4 += x * x * x * x;
        within1 += std::abs(x) < 1;
    }
    EXPECT_EQ(same_as_other_seed, 0);  // another seed, other numbers
    // Mean 0, variance 1, kurtosis 3, P(|x| < 1) = 0.6827: each within about 5 standard errors.
    EXPECT_NEAR(sum / n, 0.0, 5 / std::sqrt(double(n)));
    EXPECT_NEAR(sum2 / n, 1.0, 5 * std::sqrt(2.0 / n));
    EXPECT_NEAR(sum4 / n, 3.0, 5 * std::sqrt(96.0 / n));
    EXPECT_NEAR(double(within1) / n, 0.682689, 5 * std::sqrt(0.2166 / n));
}
