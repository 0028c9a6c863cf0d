#include "control/net_controller.h"

#include <algorithm>
#include <cmath>

#include "control/stick_map.h"
#include "core/pose_trust.h"
#include "core/units.h"

namespace pensight::control {

const char* to_string(ControlState s) {
  switch (s) {
    case ControlState::kStartup:
      return "startup";
    case ControlState::kTracking:
      return "tracking";
    case ControlState::kHold:
      return "hold";
    case ControlState::kBackOff:
      return "back_off";
  }
  return "?";
}

namespace {

ControlConfig validated(ControlConfig c) {
  validate(c, "control config");
  return c;
}

double damping_force(double linear, double quadratic, double v) {
  return linear * v + quadratic * v * std::abs(v);
}

}  // namespace

NetController::NetController(ControlConfig config)
    : config_(validated(std::move(config))),
      legs_(config_.legs),
      x_(config_.gains.surge_position, {config_.limits.surge_speed_mps}),
      u_(config_.gains.surge_velocity, {full_stick_force_n(config_.vehicle)}),
      y_(config_.gains.sway_position, {full_stick_force_n(config_.vehicle)}),
      yaw_(config_.gains.yaw, {config_.limits.yaw_rate_radps}),
      strategy_in_use_(config_.strategy) {}

void NetController::on_pose(int64_t t_ns, double d_net_m, double psi_net_rad, double quality) {
  if (!std::isfinite(d_net_m) || !std::isfinite(psi_net_rad) || d_net_m <= 0) return;
  // Blended only with a pose the loops are still acting on; after a timeout the pose is taken.
  const bool current =
      has_pose_ && seconds_between(pose_ns_, t_ns) <= config_.safety.pose_timeout_s;
  const double w = current ? pose_trust(quality) : 1.0;
  pose_ns_ = t_ns;
  d_net_m_ += w * (d_net_m - d_net_m_);
  psi_net_rad_ = wrap_angle(psi_net_rad_ + w * wrap_angle(psi_net_rad - psi_net_rad_));
  has_pose_ = true;
  pose_fresh_ = true;
}

void NetController::on_dvl(int64_t t_ns, const Eigen::Vector3d& velocity_body_mps) {
  if (!velocity_body_mps.allFinite()) return;
  const Eigen::Vector2d sample = velocity_body_mps.head<2>();
  if (has_dvl_) {
    propagate_velocity(t_ns);
    const double gate = config_.safety.dvl_gate_mps;
    const bool agrees_with_held =
        holding_sample_ && (sample - held_sample_mps_).cwiseAbs().maxCoeff() <= gate;
    if ((sample - velocity_mps_).cwiseAbs().maxCoeff() > gate && !agrees_with_held) {
      ++counters_.dvl_rejected;
      held_sample_mps_ = sample;
      holding_sample_ = true;
      return;
    }
  }
  holding_sample_ = false;
  dvl_ns_ = velocity_ns_ = t_ns;
  velocity_mps_ = sample;
  has_dvl_ = true;
}

void NetController::propagate_velocity(int64_t now_ns) {
  const auto& m = config_.vehicle;
  // Beyond the DVL timeout the velocity loops are off; the bound keeps the loop short.
  double left_s = std::min(seconds_between(velocity_ns_, now_ns), 2.0);
  if (!has_dvl_ || left_s <= 0) return;
  velocity_ns_ = now_ns;
  while (left_s > 0) {
    const double dt = std::min(left_s, 0.02);
    left_s -= dt;
    velocity_mps_.x() +=
        dt * (surge_force_n_ - feed_forward_surge(velocity_mps_.x())) / m.surge_mass_kg;
    velocity_mps_.y() +=
        dt * (sway_force_n_ - feed_forward_sway(velocity_mps_.y())) / m.sway_mass_kg;
  }
}

void NetController::on_depth(int64_t t_ns, double depth_m) {
  if (!std::isfinite(depth_m)) return;
  depth_ns_ = t_ns;
  depth_m_ = depth_m;
  has_depth_ = true;
}

double NetController::feed_forward_surge(double u_mps) const {
  return damping_force(config_.vehicle.surge_damping_linear,
                       config_.vehicle.surge_damping_quadratic, u_mps);
}

double NetController::feed_forward_sway(double v_mps) const {
  return damping_force(config_.vehicle.sway_damping_linear, config_.vehicle.sway_damping_quadratic,
                       v_mps);
}

ControlOutput NetController::update(int64_t now_ns) {
  ControlOutput out;
  out.timestamp_ns = now_ns;
  if (!started_) {
    started_ = true;
    start_ns_ = now_ns;
    last_update_ns_ = now_ns;
  }
  const double dt_s = std::max(seconds_between(last_update_ns_, now_ns), 1e-3);
  last_update_ns_ = now_ns;
  ++counters_.steps;
  const auto& safety = config_.safety;
  const auto& limits = config_.limits;
  const auto& vehicle = config_.vehicle;

  const Leg leg = legs_.current();
  out.leg = legs_.index();
  out.d_ref_m = leg.d_ref_m;
  out.heading_ref_rad = leg.heading_ref_rad;
  out.depth_ref_m = leg.depth_m;
  // The strategy: the configured one while the DVL answers.
  const bool dvl_ok = has_dvl_ && seconds_between(dvl_ns_, now_ns) <= safety.dvl_timeout_s;
  const VelocityStrategy strategy = dvl_ok ? config_.strategy : VelocityStrategy::kOpenLoop;
  if (strategy != strategy_in_use_) {
    u_.reset();
    y_.reset();
    along_ref_m_ = along_m_;
    strategy_in_use_ = strategy;
  }
  out.strategy = strategy;
  const bool feedback = strategy == VelocityStrategy::kDvlFeedback;
  propagate_velocity(now_ns);
  const double u_mps = velocity_mps_.x(), v_mps = velocity_mps_.y();
  if (feedback) along_m_ += v_mps * dt_s;

  // The state. At start-up: armed in depth hold, the speed references 0, so with the DVL the
  // velocity loops below hold the vehicle still against a current (neutral sticks would let it
  // drift onto the net) and without it the sticks are neutral.
  ControlState next = ControlState::kTracking;
  if (seconds_between(start_ns_, now_ns) < safety.startup_s) {
    next = ControlState::kStartup;
    if (has_depth_) legs_.advance(0, 0, depth_m_);  // the first leg keeps the start depth
  } else {
    if (strategy != config_.strategy) ++counters_.open_loop_fallback_steps;
    const double pose_age_s = has_pose_ ? seconds_between(pose_ns_, now_ns) : 1e9;
    if (pose_age_s > safety.backoff_after_s) {
      next = ControlState::kBackOff;
    } else if (pose_age_s > safety.pose_timeout_s) {
      next = ControlState::kHold;
    }
  }
  if (next == ControlState::kTracking && state_ != ControlState::kTracking) {
    if (state_ != ControlState::kStartup) ++counters_.recoveries;
    // The pose loops start from rest; the velocity loops keep their integrals, which hold the
    // current's force.
    x_.reset();
    yaw_.reset();
    along_ref_m_ = along_m_;
    backed_off_m_ = 0;
  }
  if (next == ControlState::kBackOff && state_ != ControlState::kBackOff) backed_off_m_ = 0;
  if (state_ == ControlState::kTracking && next != ControlState::kTracking) {
    // The surge speed reference drops to 0 (or the back-off speed): the velocity loop's integral
    // takes over the thrust that held the distance, which its feed-forward share carried before.
    u_.set_integral_term(tracking_force_n_);
  }
  state_ = next;
  out.state = state_;

  // Without the DVL, hold and back-off keep the thrust that held the distance lately (it carries
  // the current's force); the last step's alone is as noisy as the pose it came from.
  double surge_target_n = tracking_force_n_;
  double sway_target_n = 0;
  switch (state_) {
    case ControlState::kTracking: {
      if (pose_fresh_) {
        pose_fresh_ = false;
        out.u_ref_mps = x_.update(d_net_m_ - leg.d_ref_m, dt_s);
        out.r_ref_radps = -yaw_.update(rad_to_deg(psi_net_rad_ - leg.heading_ref_rad), dt_s);
      } else {
        out.u_ref_mps = x_.output();
        out.r_ref_radps = -yaw_.output();
      }
      out.v_ref_mps = leg.sway_speed_mps;
      along_ref_m_ += out.v_ref_mps * dt_s;
      surge_target_n = feed_forward_surge(out.u_ref_mps);
      tracking_force_n_ += (surge_force_n_ - tracking_force_n_) * std::min(1.0, dt_s / 2.0);
      legs_.advance(dt_s, (feedback ? v_mps : out.v_ref_mps) * dt_s, depth_m_);
      break;
    }
    case ControlState::kHold:
      ++counters_.hold_steps;
      break;
    case ControlState::kBackOff:
      backed_off_m_ += (feedback ? std::abs(u_mps) : safety.backoff_speed_mps) * dt_s;
      if (backed_off_m_ < safety.backoff_max_m) out.u_ref_mps = -safety.backoff_speed_mps;
      surge_target_n = tracking_force_n_ + feed_forward_surge(out.u_ref_mps);
      ++counters_.backoff_steps;
      break;
    case ControlState::kStartup:
      break;
  }
  if (feedback) {
    surge_target_n = feed_forward_surge(out.u_ref_mps) + u_.update(out.u_ref_mps - u_mps, dt_s);
    sway_target_n = feed_forward_sway(out.v_ref_mps) + y_.update(along_ref_m_ - along_m_, dt_s);
  } else {
    sway_target_n = feed_forward_sway(out.v_ref_mps);
  }
  // Thrust ramps: a reference step or a state change never jumps the thrusters.
  const double ramp_n = limits.force_rate_n_per_s * dt_s;
  surge_force_n_ = std::clamp(surge_target_n, surge_force_n_ - ramp_n, surge_force_n_ + ramp_n);
  sway_force_n_ = std::clamp(sway_target_n, sway_force_n_ - ramp_n, sway_force_n_ + ramp_n);
  out.surge_force_n = surge_force_n_;
  out.sway_force_n = sway_force_n_;

  if (state_ != ControlState::kStartup && has_depth_ && std::isfinite(out.depth_ref_m)) {
    out.climb_ref_mps = std::clamp(limits.depth_gain_per_s * (depth_m_ - out.depth_ref_m),
                                   -limits.climb_rate_mps, limits.climb_rate_mps);
  }
  const Eigen::Vector2d sticks =
      sticks_for_horizontal_force(vehicle, {surge_force_n_, sway_force_n_});
  out.x = sticks.x();
  out.y = sticks.y();
  out.r = std::clamp(out.r_ref_radps / vehicle.full_stick_yaw_rate_radps, -1.0, 1.0);
  out.z = std::clamp(0.5 + 0.5 * out.climb_ref_mps / vehicle.full_stick_climb_rate_mps, 0.0, 1.0);
  return out;
}

}  // namespace pensight::control
