// The T200 curve (zero in the dead band, the published 14 V maxima, monotone and continuous) and
// the allocation: ArduSub's mixing through the thruster geometry gives each axis demand a force or
// moment on that axis only (but for the pitch and roll of the horizontal thrusters sitting below
// the CG), and saturation scales the horizontal group together.
#include <gtest/gtest.h>

#include <cmath>

#include "vehicle/thrusters.h"

namespace pensight::vehicle {
namespace {

TEST(T200, DeadBandMaximaAndMonotoneCurve) {
  const T200Params t;
  for (const double pwm : {1464.0, 1480.0, 1500.0, 1532.0}) EXPECT_EQ(t200_thrust_N(t, pwm), 0.0);
  EXPECT_NEAR(t200_thrust_N(t, 1900) / kKgf_N, 4.5, 0.05);
  EXPECT_NEAR(t200_thrust_N(t, 1100) / kKgf_N, -3.5, 0.05);
  EXPECT_EQ(t200_thrust_N(t, 2000), t200_thrust_N(t, 1900));  // clamped to the range
  EXPECT_EQ(t200_thrust_N(t, 1000), t200_thrust_N(t, 1100));
  double previous = t200_thrust_N(t, 1100);
  for (double pwm = 1100.5; pwm <= 1900; pwm += 0.5) {
    const double f = t200_thrust_N(t, pwm);
    EXPECT_GE(f, previous) << pwm;
    EXPECT_LT(f - previous, 0.1) << pwm;  // continuous: no step larger than 0.1 N per 0.5 us
    previous = f;
  }
  // Between a line (0.5) and a square (0.25) at half the travel out of the band, as the
  // published table bends.
  EXPECT_NEAR(t200_thrust_N(t, 1716) / t.max_forward_N, 0.39, 0.02);
}

// Per-DOF generalized force of a demand, with thrust linear in the PWM (full output = 1 N), so
// the check is about geometry and factors, not the T200's asymmetry.
Vector6d linear_tau(const AxisDemand& d) {
  const ThrusterVector f = (mix_vectored_6dof(d).array() - 1500.0) / 400.0;
  return allocation_matrix(bluerov2_heavy_layout()) * f;
}

TEST(Allocation, EachStickPushesItsOwnAxis) {
  const double z = bluerov2_heavy_layout()[0].position_body_m.z();  // horizontal thrusters
  struct Case {
    AxisDemand demand;
    int axis;
  };
  for (const Case& c :
       {Case{{.forward = 0.5}, 0}, Case{{.lateral = 0.5}, 1}, Case{{.throttle = 0.5}, 2},
        Case{{.roll = 0.5}, 3}, Case{{.pitch = 0.5}, 4}, Case{{.yaw = 0.5}, 5}}) {
    Vector6d tau = linear_tau(c.demand);
    const double sign = c.axis == 2 ? -1.0 : 1.0;  // throttle up is -z in FRD
    EXPECT_GT(sign * tau[c.axis], 0.2) << "axis " << c.axis;
    tau[c.axis] = 0;
    // Thrust below the CG: surge pitches up (M = z X), sway rolls left (K = -z Y).
    if (c.axis == 0) tau[4] -= z * linear_tau(c.demand)[0];
    if (c.axis == 1) tau[3] += z * linear_tau(c.demand)[1];
    EXPECT_LT(tau.norm(), 1e-12) << "axis " << c.axis << ": " << tau.transpose();
  }
}

TEST(Allocation, RealThrustersKeepSurgeAndYawClean) {
  // With the T200's weaker reverse thrust the opposed thrusters still cancel in pairs.
  const T200Params t;
  const AllocationMatrix B = allocation_matrix(bluerov2_heavy_layout());
  const auto tau = [&](const AxisDemand& d) {
    const ThrusterVector pwm = mix_vectored_6dof(d);
    ThrusterVector f;
    for (int i = 0; i < kThrusterCount; ++i) f[i] = t200_thrust_N(t, pwm[i]);
    return Vector6d(B * f);
  };
  const Vector6d surge = tau({.forward = 0.5});
  EXPECT_GT(surge[0], 30.0);
  EXPECT_NEAR(surge[1], 0, 1e-12);
  EXPECT_NEAR(surge[5], 0, 1e-12);
  const Vector6d yaw = tau({.yaw = 0.5});
  EXPECT_GT(yaw[5], 4.0);
  EXPECT_LT(yaw.head<5>().norm(), 1e-12);
}

TEST(Allocation, SaturationScalesTheHorizontalGroupTogether) {
  const ThrusterVector pwm = mix_vectored_6dof({.yaw = 1.0, .forward = 1.0});
  ThrusterVector expected;
  expected << 1500, 1100, 1500, 1900, 1500, 1500, 1500, 1500;  // (yaw + forward) / 2 per motor
  EXPECT_EQ(pwm, expected);
  EXPECT_EQ(mix_vectored_6dof({}), ThrusterVector::Constant(1500));
}

}  // namespace
}  // namespace pensight::vehicle
