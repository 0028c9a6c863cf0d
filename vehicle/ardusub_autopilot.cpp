#include "vehicle/ardusub_autopilot.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/units.h"

namespace pensight::vehicle {
namespace {

// ArduSub keeps the yaw rate at zero this long after the stick centres before it takes the
// heading to hold, so the turn's inertia does not pull the heading back (mode_althold.cpp).
constexpr double kYawSettle_s = 0.25;

double stick(double value) {
  return std::clamp(value, -1.0, 1.0);
}

}  // namespace

ArduSubAutopilot::ArduSubAutopilot(const AutopilotParams& params)
    : params_(params), dt_s_(1.0 / params.rate_hz), rng_(params.noise_seed) {}

double ArduSubAutopilot::run_pid(const PidGains& g, PidState& s, double error) const {
  s.integral = std::clamp(s.integral + g.i * error * dt_s_, -g.imax, g.imax);
  if (s.started && g.d > 0) {
    const double raw = (error - s.previous_error) / dt_s_;
    const double alpha =
        g.filter_hz > 0 ? dt_s_ / (dt_s_ + 1 / (2 * std::numbers::pi * g.filter_hz)) : 1.0;
    s.derivative += alpha * (raw - s.derivative);
  }
  s.previous_error = error;
  s.started = true;
  return g.p * error + s.integral + g.d * s.derivative;
}

double ArduSubAutopilot::hold_depth(double throttle_stick, double depth_m, double climb_mps) {
  const double dz = params_.throttle_deadzone;
  double climb_target_mps = 0;
  if (std::abs(throttle_stick) > dz) {
    climb_target_mps = std::copysign(
        params_.max_climb_rate_mps * (std::abs(throttle_stick) - dz) / (1 - dz), throttle_stick);
    depth_target_m_ = depth_m;
  } else {
    climb_target_mps = std::clamp(params_.depth_p * (depth_m - depth_target_m_),
                                  -params_.max_climb_rate_mps, params_.max_climb_rate_mps);
  }
  return stick(run_pid(params_.climb_rate, climb_, climb_target_mps - climb_mps));
}

ThrusterVector ArduSubAutopilot::update(const ManualCommand& cmd, const RigidBodyState& truth) {
  if (!cmd.armed) {
    engaged_ = false;
    return ThrusterVector::Constant(1500.0);
  }
  std::normal_distribution<double> unit_normal(0.0, 1.0);
  const Eigen::Matrix3d R = truth.q_pen_body.toRotationMatrix();
  Eigen::Vector3d rpy = rpy_from_rotation(R);
  for (int i = 0; i < 3; ++i) rpy[i] += params_.attitude_noise_rad * unit_normal(rng_);
  const double depth_m = truth.position_pen_m.z() + params_.depth_noise_m * unit_normal(rng_);
  const double climb_mps = -(R * truth.nu_body.head<3>()).z();
  const Eigen::Vector3d rate = truth.nu_body.tail<3>();

  if (!engaged_ || cmd.mode != mode_) {
    engaged_ = true;
    mode_ = cmd.mode;
    heading_target_rad_ = rpy[2];
    depth_target_m_ = depth_m;
    since_yaw_input_s_ = kYawSettle_s;
    roll_ = pitch_ = yaw_ = climb_ = PidState{};
  }

  const double gain = params_.pilot_gain;
  AxisDemand d;
  d.forward = stick(gain * cmd.x);
  d.lateral = stick(gain * cmd.y);
  const double yaw_stick = stick(gain * cmd.r);
  const double throttle_stick = stick(gain * (2 * std::clamp(cmd.z, 0.0, 1.0) - 1));
  if (cmd.mode == FlightMode::kManual) {
    d.yaw = yaw_stick;
    d.throttle = throttle_stick;
    return mix_vectored_6dof(d);
  }

  d.roll = stick(
      run_pid(params_.rate_roll_pitch, roll_, params_.angle_p * wrap_angle(-rpy[0]) - rate[0]));
  d.pitch = stick(
      run_pid(params_.rate_roll_pitch, pitch_, params_.angle_p * wrap_angle(-rpy[1]) - rate[1]));
  double yaw_rate_target = yaw_stick * params_.max_yaw_rate_radps;
  if (yaw_stick != 0 || since_yaw_input_s_ < kYawSettle_s) {
    since_yaw_input_s_ = yaw_stick != 0 ? 0.0 : since_yaw_input_s_ + dt_s_;
    heading_target_rad_ = rpy[2];
  } else {
    yaw_rate_target = params_.angle_p * wrap_angle(heading_target_rad_ - rpy[2]);
  }
  d.yaw = stick(run_pid(params_.rate_yaw, yaw_, yaw_rate_target - rate[2]));
  d.throttle = cmd.mode == FlightMode::kAltHold ? hold_depth(throttle_stick, depth_m, climb_mps)
                                                : throttle_stick;
  return mix_vectored_6dof(d);
}

}  // namespace pensight::vehicle
