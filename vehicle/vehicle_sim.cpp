#include "vehicle/vehicle_sim.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace pensight::vehicle {
namespace {

// Checks the parameters before any member is built from them.
const VehicleParams& checked(const VehicleParams& params) {
  check_params(params);
  return params;
}

void check_state(const RigidBodyState& s) {
  const bool finite =
      s.position_pen_m.allFinite() && s.nu_body.allFinite() && s.q_pen_body.coeffs().allFinite();
  if (!finite || std::abs(s.q_pen_body.norm() - 1) > 1e-6) {
    throw Error("VehicleSim: the initial state must be finite with a unit quaternion");
  }
}

}  // namespace

VehicleSim::VehicleSim(const VehicleParams& params, const RigidBodyState& initial)
    : params_(checked(params)),
      hull_(params.hull),
      current_(params.current),
      autopilot_(params.autopilot),
      allocation_(allocation_matrix(params.thrusters)),
      state_(initial),
      physics_dt_s_(1.0 / params.physics_rate_hz),
      steps_per_autopilot_(std::llround(params.physics_rate_hz / params.autopilot.rate_hz)),
      thrust_blend_(params.t200.time_constant_s > 0
                        ? 1 - std::exp(-physics_dt_s_ / params.t200.time_constant_s)
                        : 1.0) {
  check_state(initial);
}

void VehicleSim::set_command(const ManualCommand& command) {
  if (!Eigen::Vector4d(command.x, command.y, command.z, command.r).allFinite()) {
    throw Error("VehicleSim::set_command: the sticks x, y, z, r must be finite");
  }
  command_ = command;
}

void VehicleSim::advance(double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0)) {
    throw Error("VehicleSim::advance: dt_s must be finite and >= 0 (is " + std::to_string(dt_s) +
                ")");
  }
  requested_s_ += dt_s;
  // Half a nanosecond of slack keeps sums of decimal steps (10 x 0.1 s) from losing a step.
  while (static_cast<double>(steps_ + 1) * physics_dt_s_ <= requested_s_ + 5e-10) step();
}

void VehicleSim::step() {
  if (steps_ % steps_per_autopilot_ == 0) {
    pwm_us_ = autopilot_.update(command_, state_);
    for (int i = 0; i < kThrusterCount; ++i) {
      target_thrust_N_[i] = t200_thrust_N(params_.t200, pwm_us_[i]);
    }
  }
  thrust_N_ += thrust_blend_ * (target_thrust_N_ - thrust_N_);
  state_ = hull_.step(state_, allocation_ * thrust_N_, current_.velocity_pen_mps(), physics_dt_s_);
  current_.advance(physics_dt_s_);
  ++steps_;
}

}  // namespace pensight::vehicle
