#include "control/pid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pensight::control {
namespace {

TEST(Pid, ProportionalAndNoDerivativeKickOnTheFirstStep) {
  Pid pid({2.0, 0.0, 5.0}, {});
  EXPECT_DOUBLE_EQ(pid.update(0.3, 0.1), 0.6);  // no previous error: no derivative
  EXPECT_DOUBLE_EQ(pid.update(0.4, 0.1), 2.0 * 0.4 + 5.0 * (0.4 - 0.3) / 0.1);
  EXPECT_DOUBLE_EQ(pid.update(0.4, 0.1, -1.0), 2.0 * 0.4 - 5.0);  // a measured rate wins
}

TEST(Pid, IntegralAndReset) {
  Pid pid({0.0, 1.0, 0.0}, {});
  for (int i = 0; i < 10; ++i) pid.update(0.5, 0.1);
  EXPECT_NEAR(pid.output(), 0.5, 1e-12);
  pid.reset();
  EXPECT_EQ(pid.output(), 0.0);
  EXPECT_EQ(pid.integral(), 0.0);
}

// A saturated loop must not wind up: once the error changes sign the output leaves the limit at
// once, where a plain integrator would stay saturated for as long as it was wound.
TEST(Pid, NoWindupWhileSaturated) {
  Pid pid({1.0, 2.0, 0.0}, {1.0});
  for (int i = 0; i < 200; ++i) pid.update(5.0, 0.1);  // 20 s far off: saturated throughout
  EXPECT_DOUBLE_EQ(pid.output(), 1.0);
  EXPECT_LE(pid.integral() * 2.0, 1.0 + 1e-12);
  const double after = pid.update(-0.5, 0.1);
  EXPECT_LT(after, 1.0);
  // A plain integrator would hold 2 * (5 * 20) = 200 and stay at the limit.
  Pid windup_free({1.0, 2.0, 0.0}, {});
  for (int i = 0; i < 200; ++i) windup_free.update(5.0, 0.1);
  EXPECT_GT(windup_free.update(-0.5, 0.1), 100.0);
}

TEST(Pid, IntegralTermCanBeSetForABumplessTransfer) {
  Pid pid({2.0, 0.5, 0.0}, {10.0});
  pid.set_integral_term(4.0);
  EXPECT_DOUBLE_EQ(pid.update(0.0, 0.1), 4.0);
  pid.set_integral_term(40.0);  // beyond the output limit: clamped
  EXPECT_DOUBLE_EQ(pid.update(0.0, 0.1), 10.0);
  Pid no_integral({2.0, 0.0, 0.0}, {});
  no_integral.set_integral_term(4.0);
  EXPECT_DOUBLE_EQ(no_integral.update(0.0, 0.1), 0.0);
}

TEST(Pid, RateLimitRampsAStep) {
  Pid pid({10.0, 0.0, 0.0}, {100.0, 2.0});
  EXPECT_NEAR(pid.update(1.0, 0.1), 0.2, 1e-12);
  EXPECT_NEAR(pid.update(1.0, 0.1), 0.4, 1e-12);
  for (int i = 0; i < 100; ++i) pid.update(1.0, 0.1);
  EXPECT_NEAR(pid.output(), 10.0, 1e-12);
}

TEST(Pid, NonFiniteErrorKeepsTheLastOutput) {
  Pid pid({1.0, 1.0, 1.0}, {});
  pid.update(0.2, 0.1);
  const double last = pid.output();
  EXPECT_EQ(pid.update(std::nan(""), 0.1), last);
  EXPECT_EQ(pid.update(INFINITY, 0.1), last);
  EXPECT_EQ(pid.update(0.2, 0.0), last);  // no time passed
}

}  // namespace
}  // namespace pensight::control
