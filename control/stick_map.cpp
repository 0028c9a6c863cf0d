#include "control/stick_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pensight::control {
namespace {

constexpr double kPwmSpanUs = 400, kPwmNeutralUs = 1500, kSmallForceN = 0.5;

double forward_thrust_n(const VehicleModel& m, double pwm_us) {
  if (pwm_us <= m.deadband_high_us) return 0;
  const double f =
      (pwm_us - m.deadband_high_us) / (kPwmNeutralUs + kPwmSpanUs - m.deadband_high_us);
  return m.max_forward_n * std::pow(std::min(f, 1.0), m.thrust_exponent);
}

double reverse_thrust_n(const VehicleModel& m, double pwm_us) {
  if (pwm_us >= m.deadband_low_us) return 0;
  const double f = (m.deadband_low_us - pwm_us) / (m.deadband_low_us - kPwmNeutralUs + kPwmSpanUs);
  return m.max_reverse_n * std::pow(std::min(f, 1.0), m.thrust_exponent);
}

// The stick at which the first motor leaves the dead band.
double deadband_edge_stick(const VehicleModel& m) {
  const double edge_us =
      std::min(m.deadband_high_us - kPwmNeutralUs, kPwmNeutralUs - m.deadband_low_us);
  return std::min(1.0, edge_us / (kPwmSpanUs * m.pilot_gain));
}

}  // namespace

double axis_force_n(const VehicleModel& m, double stick) {
  const double s = std::clamp(stick, -1.0, 1.0);
  const double o = std::abs(s) * m.pilot_gain;
  const double per_pair = forward_thrust_n(m, kPwmNeutralUs + kPwmSpanUs * o) +
                          reverse_thrust_n(m, kPwmNeutralUs - kPwmSpanUs * o);
  return std::copysign(2 * std::cos(std::numbers::pi / 4) * per_pair, s);
}

double stick_for_axis_force(const VehicleModel& m, double force_n) {
  if (!std::isfinite(force_n) || force_n == 0) return 0;
  const double target = std::abs(force_n);
  const double edge = deadband_edge_stick(m);
  if (target < kSmallForceN) {
    // Up to the stick that makes kSmallForceN, linearly from 0.
    return std::copysign(stick_for_axis_force(m, kSmallForceN) * target / kSmallForceN, force_n);
  }
  if (axis_force_n(m, 1.0) <= target) return std::copysign(1.0, force_n);
  double lo = edge, hi = 1.0;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (axis_force_n(m, mid) < target ? lo : hi) = mid;
  }
  return std::copysign(hi, force_n);
}

}  // namespace pensight::control
