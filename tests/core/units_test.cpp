#include "core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <random>

#include "core/net_angles.h"
#include "tests/support/test_seed.h"

namespace pensight {
namespace {

TEST(Units, SecondsToNsRoundsAsLlroundAndTowardZeroAsACast) {
  static_assert(seconds_to_ns(1.5) == 1'500'000'000);
  static_assert(seconds_to_ns(-1.5) == -1'500'000'000);
  // 4.1 * 1e9 falls just below 4.1e9 in double.
  EXPECT_EQ(seconds_to_ns(4.1), 4'100'000'000);
  EXPECT_EQ(seconds_to_ns_toward_zero(4.1), 4'099'999'999);
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> window_s(-100, 100), epoch_s(1.6e9, 1.8e9);
  for (int i = 0; i < 100000; ++i) {
    // Durations, epoch timestamps and sub-nanosecond values (halves included).
    for (const double s : {window_s(rng), epoch_s(rng), std::ldexp(window_s(rng), -37)}) {
      ASSERT_EQ(seconds_to_ns(s), std::llround(s * 1e9)) << s;
      ASSERT_EQ(seconds_to_ns_toward_zero(s), static_cast<int64_t>(s * 1e9)) << s;
    }
  }
}

TEST(Units, NsToSeconds) {
  EXPECT_EQ(ns_to_seconds(1'500'000'000), 1.5);
  EXPECT_EQ(ns_to_seconds(-250'000'000), -0.25);
  EXPECT_EQ(seconds_between(1'700'000'000'000'000'000, 1'700'000'002'500'000'000), 2.5);
}

TEST(NetAngles, NormalAndPlaneFormsAgree) {
  const NetAngles square = net_angles_from_normal_C({0, 0, 1});
  EXPECT_EQ(square.psi_rad, 0.0);
  EXPECT_EQ(square.pitch_rad, 0.0);
  EXPECT_NEAR(net_angles_from_normal_C({-1, 0, 1}).psi_rad, std::numbers::pi / 4, 1e-15);
  EXPECT_NEAR(net_angles_from_normal_C({0, 1, 1}).pitch_rad, -std::numbers::pi / 4, 1e-15);
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> slope(-2, 2), scale(0.1, 10);
  for (int i = 0; i < 1000; ++i) {
    const double a = slope(rng), b = slope(rng);
    // The plane z = a x + b y + c has the normal (-a, -b, 1), of any length.
    const NetAngles n = net_angles_from_normal_C(scale(rng) * Eigen::Vector3d(-a, -b, 1));
    const NetAngles p = net_angles_from_plane_C(a, b);
    ASSERT_NEAR(n.psi_rad, p.psi_rad, 1e-14);
    ASSERT_NEAR(n.pitch_rad, p.pitch_rad, 1e-14);
  }
}

}  // namespace
}  // namespace pensight
