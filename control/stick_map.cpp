#include "control/stick_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vehicle/thrusters.h"

namespace pensight::control {
namespace {

constexpr double kSmallForceN = 0.5;

vehicle::T200Params t200(const VehicleModel& m) {
  vehicle::T200Params t;
  t.deadband_low_us = m.deadband_low_us;
  t.deadband_high_us = m.deadband_high_us;
  t.max_forward_N = m.max_forward_n;
  t.max_reverse_N = m.max_reverse_n;
  t.curve_exponent = m.thrust_exponent;
  return t;
}

const vehicle::AllocationMatrix& allocation() {
  static const vehicle::AllocationMatrix b =
      vehicle::allocation_matrix(vehicle::bluerov2_heavy_layout());
  return b;
}

// The force along a diagonal of the vehicle (N) when the sticks' sum (or difference) is `a`: the
// two thrusters on that diagonal run at +-a times the pilot gain, the other two at 0.
double diagonal_force_n(const VehicleModel& m, double a) {
  return horizontal_force_n(m, a / 2, a / 2).norm() * (a < 0 ? -1 : 1);
}

// The sum (or difference) of sticks whose diagonal pair makes `force_n`, by bisection; below
// kSmallForceN linearly to 0 from the one that makes it.
double diagonal_for_force(const VehicleModel& m, double force_n) {
  const double target = std::max(std::abs(force_n), kSmallForceN);
  double lo = 0, hi = 2;
  if (diagonal_force_n(m, hi) <= target) {
    lo = hi;
  } else {
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (diagonal_force_n(m, mid) < target ? lo : hi) = mid;
    }
  }
  return std::copysign(hi * std::min(1.0, std::abs(force_n) / kSmallForceN), force_n);
}

}  // namespace

Eigen::Vector2d horizontal_force_n(const VehicleModel& m, double x, double y) {
  vehicle::AxisDemand demand;
  demand.forward = std::clamp(x, -1.0, 1.0) * m.pilot_gain;
  demand.lateral = std::clamp(y, -1.0, 1.0) * m.pilot_gain;
  const vehicle::ThrusterVector pwm = vehicle::mix_vectored_6dof(demand);
  const vehicle::T200Params t = t200(m);
  vehicle::ThrusterVector thrust;
  for (int i = 0; i < vehicle::kThrusterCount; ++i) thrust[i] = vehicle::t200_thrust_N(t, pwm[i]);
  return (allocation() * thrust).head<2>();
}

double full_stick_force_n(const VehicleModel& m) {
  return horizontal_force_n(m, 1, 0).x();
}

Eigen::Vector2d sticks_for_horizontal_force(const VehicleModel& m, const Eigen::Vector2d& force_n) {
  if (!force_n.allFinite()) return Eigen::Vector2d::Zero();
  // The mixer runs thrusters 2 and 3 at -+(x + y) and 1 and 4 at -+(x - y) (times the gain), each
  // pair pushing along one diagonal: X = (D(x + y) + D(x - y)) / sqrt 2, Y = (D(x + y) -
  // D(x - y)) / sqrt 2 for the diagonal force D. So each diagonal's force is known from (X, Y)
  // and inverted alone.
  const double a = diagonal_for_force(m, (force_n.x() + force_n.y()) / std::numbers::sqrt2);
  const double b = diagonal_for_force(m, (force_n.x() - force_n.y()) / std::numbers::sqrt2);
  // Sticks stay in [-1, 1]: a force beyond reach keeps its direction.
  const double over = std::max(1.0, (std::abs(a) + std::abs(b)) / 2);
  return {(a + b) / 2 / over, (a - b) / 2 / over};
}

}  // namespace pensight::control
