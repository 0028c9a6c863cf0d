#include "vehicle/thrusters.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace pensight::vehicle {
namespace {

// ArduPilot libraries/AP_Motors/AP_Motors6DOF.cpp, SUB_FRAME_VECTORED_6DOF.
struct MotorFactors {
  double roll, pitch, yaw, throttle, forward, lateral;
};
constexpr std::array<MotorFactors, kThrusterCount> kVectored6dof = {{
    {0, 0, 1, 0, -1, 1},
    {0, 0, -1, 0, -1, -1},
    {0, 0, -1, 0, 1, 1},
    {0, 0, 1, 0, 1, -1},
    {1, -1, 0, -1, 0, 0},
    {-1, -1, 0, -1, 0, 0},
    {1, 1, 0, -1, 0, 0},
    {-1, 1, 0, -1, 0, 0},
}};

}  // namespace

double t200_thrust_N(const T200Params& t, double pwm_us) {
  const double pwm = std::clamp(pwm_us, t.pwm_min_us, t.pwm_max_us);
  if (pwm > t.deadband_high_us) {
    const double x = (pwm - t.deadband_high_us) / (t.pwm_max_us - t.deadband_high_us);
    return t.max_forward_N * std::pow(x, t.curve_exponent);
  }
  if (pwm < t.deadband_low_us) {
    const double x = (t.deadband_low_us - pwm) / (t.deadband_low_us - t.pwm_min_us);
    return -t.max_reverse_N * std::pow(x, t.curve_exponent);
  }
  return 0.0;
}

AllocationMatrix allocation_matrix(const ThrusterLayout& layout) {
  AllocationMatrix B;
  for (int i = 0; i < kThrusterCount; ++i) {
    const ThrusterMount& m = layout[i];
    B.col(i) << m.direction_body, m.position_body_m.cross(m.direction_body);
  }
  return B;
}

ThrusterVector mix_vectored_6dof(const AxisDemand& d) {
  ThrusterVector vertical, horizontal;
  for (int i = 0; i < kThrusterCount; ++i) {
    const MotorFactors& f = kVectored6dof[i];
    vertical[i] = d.roll * f.roll + d.pitch * f.pitch + d.throttle * f.throttle;
    horizontal[i] = d.yaw * f.yaw + d.forward * f.forward + d.lateral * f.lateral;
  }
  const double vertical_max = std::max(1.0, vertical.cwiseAbs().maxCoeff());
  const double horizontal_max = std::max(1.0, horizontal.cwiseAbs().maxCoeff());
  const ThrusterVector out =
      (vertical / vertical_max + horizontal / horizontal_max).cwiseMax(-1.0).cwiseMin(1.0);
  return (1500.0 + 400.0 * out.array()).matrix();
}

}  // namespace pensight::vehicle
