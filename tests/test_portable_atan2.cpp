// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/numerics/portable_atan2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace cf = canonform;

TEST(PortableAtan2, AgreesWithLibmToAFewUnitsInTheLastPlace) {
    // Arguments over 40 binary orders of magnitude and every octant (ldexp is exact, so the
    // arguments themselves are the same on every CPU).
    std::mt19937_64 g(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double max_abs = 0, max_rel = 0;
    for (int i = 0; i < 200000; ++i) {
        const double y = std::ldexp(u(g), static_cast<int>(g() % 40) - 20);
        const double x = std::ldexp(u(g), static_cast<int>(g() % 40) - 20);
        const double a = cf::numerics::portable_atan2(y, x), b = std::atan2(y, x);
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
                EXPECT_NEAR(cf::numerics::portable_atan2(sy * t, sx * 1.0), std::atan2(sy * t, sx * 1.0), 4.5e-16) << t;
    }
}

TEST(PortableAtan2, SpecialValuesAsInC) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(cf::numerics::portable_atan2(0.0, 1.0), 0.0);
    EXPECT_TRUE(std::signbit(cf::numerics::portable_atan2(-0.0, 1.0)));
    EXPECT_EQ(cf::numerics::portable_atan2(0.0, 0.0), 0.0);
    EXPECT_EQ(cf::numerics::portable_atan2(0.0, -0.0), M_PI);
    EXPECT_EQ(cf::numerics::portable_atan2(-0.0, -1.0), -M_PI);
    EXPECT_EQ(cf::numerics::portable_atan2(1.0, 0.0), M_PI / 2);
    EXPECT_EQ(cf::numerics::portable_atan2(-1.0, -0.0), -M_PI / 2);
    EXPECT_EQ(cf::numerics::portable_atan2(1.0, 1.0), M_PI / 4);
    EXPECT_EQ(cf::numerics::portable_atan2(1.0, inf), 0.0);
    EXPECT_EQ(cf::numerics::portable_atan2(inf, 1.0), M_PI / 2);
    EXPECT_NEAR(cf::numerics::portable_atan2(inf, -inf), 3 * M_PI / 4, 4.5e-16);
    EXPECT_TRUE(std::isnan(cf::numerics::portable_atan2(std::nan(""), 1.0)));
    EXPECT_TRUE(std::isnan(cf::numerics::portable_atan2(1.0, std::nan(""))));
}
