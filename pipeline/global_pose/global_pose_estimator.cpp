// GlobalPoseEstimator, part 1 of 4: the time-ordered buffer, roll-back and re-apply of late
// samples, the estimate at a time, the counters.
#include "pipeline/global_pose/global_pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "core/error.h"
#include "core/log.h"
#include "core/units.h"

#include "pipeline/global_pose/estimator_detail.h"

namespace pensight::global_pose {
using namespace detail;

std::string describe(const GlobalPoseCounters& c) {
  std::string out;
  const std::pair<const char*, const SensorCounters*> rows[] = {
      {"DVL velocity", &c.dvl_velocity}, {"DVL plane", &c.dvl_plane},
      {"pressure depth", &c.depth},      {"attitude", &c.attitude},
      {"vision fix", &c.vision_fix},     {"vision d_net/psi_net", &c.vision_relative},
      {"net texture", &c.net_texture}};
  for (const auto& [name, s] : rows) {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "%-21s received %d, accepted %d, gated out %d, re-locked %d, invalid %d, "
                  "duplicates %d, out of order %d, too late %d\n",
                  name, s->received, s->accepted, s->rejected - s->spikes, s->relocked, s->invalid,
                  s->duplicates, s->out_of_order, s->too_late);
    out += line;
    if (s == &c.dvl_velocity) {
      std::snprintf(line, sizeof(line), "%-21s spikes rejected %d\n", "", s->spikes);
      out += line;
    }
    if (s == &c.vision_fix) {
      std::snprintf(line, sizeof(line),
                    "%-21s not trusted to lock %d, position re-initialised %d\n", "",
                    s->not_lockable, s->reinitialised);
      out += line;
    }
  }
  return out;
}

GlobalPoseEstimator::GlobalPoseEstimator(GlobalPoseEstimatorConfig config)
    : cfg_(std::move(config)) {
  validate(cfg_);
  if (cfg_.flat_panel) {
    wall_ = NetWall::flat_panel(cfg_.pen_radius_m, cfg_.flat_panel->plane_point_m.head<2>(),
                                cfg_.flat_panel->plane_normal.head<2>());
    cfg_.circle.radius_m = kFlatPanelFitRadius_m;
  } else {
    wall_ = NetWall::cylinder(cfg_.pen_radius_m);
    cfg_.circle.radius_m = cfg_.pen_radius_m;
  }
  cfg_.dvl_spikes.noise_mps = cfg_.noise.dvl_velocity_mps;
  dvl_spikes_ = DvlSpikeTest(cfg_.dvl_spikes);
  if (!cfg_.has_dvl)
    log_warning(
        "global pose: no DVL (dvl0/ missing): running without velocity aiding; rho_g follows the "
        "attitude yaw and the vision fixes only, and is NaN where neither constrains it");
  if (!cfg_.has_attitude)
    log_warning(
        "global pose: no attitude (imu0/attitude.csv missing): roll = pitch = 0 is assumed for "
        "levelling and the heading is not aided, so rho_g drifts with the DVL");
  if (!cfg_.has_pressure)
    log_warning("global pose: no pressure sensor (pressure0/ missing): z_g is NaN");
  if (cfg_.use_dvl_plane && cfg_.has_dvl && !cfg_.dvl_beams)
    log_info("global pose: no DVL beam geometry given; DVL net-plane updates are off");
}

void GlobalPoseEstimator::warn_once(int id, const std::string& message) {
  if (warned_[static_cast<size_t>(id)]) return;
  warned_[static_cast<size_t>(id)] = true;
  log_warning("global pose: " + message + " (counted; further ones are not logged)");
}

void GlobalPoseEstimator::add(const DvlSample& s) {
  if (!s.valid || !s.velocity_B_mps.allFinite()) {
    enqueue({s.timestamp_ns, kDvl, s}, arrival_.dvl_velocity);  // counted invalid when applied
    return;
  }
  const int spikes_before = dvl_spikes_.spikes();
  for (const DvlSample& r : dvl_spikes_.push(s, dvl_velocity_pen(s))) {
    // A span predicted with other process noise than its samples show: apply it again.
    if (const auto from = motion_.add(r.timestamp_ns, dvl_velocity_pen(r)))
      while (!history_.empty() && history_.back().event.t_ns > *from) undo_last_applied();
    enqueue({r.timestamp_ns, kDvl, r}, arrival_.dvl_velocity);
  }
  if (dvl_spikes_.spikes() > spikes_before)
    warn_once(kWarnDvlSpike, "DVL velocity spike rejected (beyond the vehicle's acceleration)");
}

Eigen::Vector3d GlobalPoseEstimator::dvl_velocity_pen(const DvlSample& s) const {
  const auto a = attitude_.at(s.timestamp_ns, cfg_.max_attitude_gap_s);
  const double heading =
      a && std::isfinite(a->yaw_rad) ? a->yaw_rad : (state_.initialised ? state_.ekf.x(kPsi) : 0.0);
  return rotation_from_rpy(a ? a->roll_rad : 0.0, a ? a->pitch_rad : 0.0, heading) *
         s.velocity_B_mps;
}

ProcessNoise GlobalPoseEstimator::process_noise(int64_t t0_ns, int64_t t1_ns) const {
  ProcessNoise q = cfg_.noise.process;
  if (motion_.quiet(t0_ns, t1_ns)) q.horizontal_accel = q.quiet_horizontal_accel;
  return q;
}

void GlobalPoseEstimator::undo_last_applied() {
  state_ = history_.back().before;
  pending_.insert(pending_.begin(), std::move(history_.back().event));
  history_.pop_back();
}

void GlobalPoseEstimator::add(const PressureSample& s) {
  enqueue({s.timestamp_ns, kDepth, s}, arrival_.depth);
}
void GlobalPoseEstimator::add(const NetObservation& obs) {
  if (!obs.quality.empty() && obs.quality.size() != obs.points_C.size())
    throw Error("global pose: camera frame " + std::to_string(obs.t_ns) + " has " +
                std::to_string(obs.quality.size()) + " qualities for " +
                std::to_string(obs.points_C.size()) +
                " net points; give one quality per point, or none");
  enqueue({obs.t_ns, kCamera, obs}, arrival_.vision_fix);
}
void GlobalPoseEstimator::add(const AttitudeSample& s) {
  if (attitude_.insert(s)) {
    enqueue({s.timestamp_ns, kAttitude, s}, arrival_.attitude);
    return;
  }
  ++arrival_.attitude.received;
  if (std::isfinite(s.roll_rad) && std::isfinite(s.pitch_rad)) {
    ++arrival_.attitude.duplicates;
    warn_once(kWarnDuplicate, "duplicate timestamp dropped");
  } else {
    ++arrival_.attitude.invalid;
  }
}

void GlobalPoseEstimator::enqueue(Event e, SensorCounters& arrival) {
  ++arrival.received;
  const auto key_less = [](const Event& a, const Event& b) {
    return a.t_ns != b.t_ns ? a.t_ns < b.t_ns : a.kind < b.kind;
  };
  const auto range = std::equal_range(pending_.begin(), pending_.end(), e, key_less);
  bool duplicate = range.first != range.second;
  for (const auto& h : history_)
    duplicate = duplicate || (h.event.t_ns == e.t_ns && h.event.kind == e.kind);
  if (duplicate) {
    ++arrival.duplicates;
    warn_once(kWarnDuplicate, "duplicate timestamp dropped");
    return;
  }
  if (e.t_ns < state_.last_time_ns) {
    const int64_t window_start = state_.last_time_ns - seconds_to_ns_toward_zero(cfg_.history_s);
    // Before the oldest kept sample only while nothing has been trimmed (then the oldest
    // sample's snapshot is the initial state).
    const bool covered =
        e.t_ns >= window_start &&
        (!history_trimmed_ || (!history_.empty() && e.t_ns >= history_.front().event.t_ns));
    if (!covered) {
      ++arrival.too_late;
      warn_once(kWarnTooLate, "sample older than the re-apply window dropped");
      return;
    }
    ++arrival.out_of_order;
    warn_once(kWarnOutOfOrder, "out-of-order sample re-applied in timestamp order");
    // Roll back to just before the late sample; what followed it is applied again.
    while (!history_.empty() && key_less(e, history_.back().event)) undo_last_applied();
  }
  pending_.insert(std::upper_bound(pending_.begin(), pending_.end(), e, key_less), std::move(e));
}

GlobalPose GlobalPoseEstimator::estimate(int64_t t_ns) {
  dvl_spikes_.expire(t_ns);
  size_t n = 0;
  while (n < pending_.size() && pending_[n].t_ns <= t_ns) {
    history_.push_back({std::move(pending_[n]), state_});
    apply(history_.back().event);
    ++n;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
  if (n > 0) {
    const int64_t window_start = state_.last_time_ns - seconds_to_ns_toward_zero(cfg_.history_s);
    while (!history_.empty() && history_.front().event.t_ns < window_start) {
      history_.pop_front();
      history_trimmed_ = true;
    }
    attitude_.trim_before(window_start - seconds_to_ns_toward_zero(cfg_.max_attitude_gap_s));
    motion_.trim_before(window_start);
  }

  GlobalPose out;
  out.t_ns = t_ns;
  if (!state_.initialised) {
    out.z_g_m = cfg_.has_pressure ? state_.last_depth_m : kNaN;
    return out;
  }
  PenEkf ekf = state_.ekf;
  ekf.predict_to(t_ns, process_noise(ekf.t_ns, t_ns));
  const StateVector& x = ekf.x;
  const double r = std::hypot(x(kX), x(kY));
  const double rho = std::atan2(x(kY), x(kX));
  // (r, rho, z, psi) from (x, y, z, psi).
  Eigen::Matrix<double, 4, kStateDim> J = Eigen::Matrix<double, 4, kStateDim>::Zero();
  J(0, kX) = x(kX) / r;
  J(0, kY) = x(kY) / r;
  J(1, kX) = -x(kY) / (r * r);
  J(1, kY) = x(kX) / (r * r);
  J(2, kZ) = 1;
  J(3, kPsi) = 1;
  out.covariance = J * ekf.P * J.transpose();
  out.r_g_m = r;
  // Rotating the vehicle and its heading together about the pen axis changes no vision
  // measurement, so rho_g needs the DVL or the attitude yaw; without them the EKF's linearisation
  // would report a falsely small covariance.
  const bool rho_aided = state_.last_rho_aid_ns != kNever &&
                         seconds_between(state_.last_rho_aid_ns, t_ns) <= cfg_.max_unaided_s;
  const bool rho_known = rho_aided && std::sqrt(out.covariance(1, 1)) <= cfg_.max_rho_sigma_rad;
  out.rho_g_rad = rho_known ? wrap_angle(rho) : kNaN;
  out.psi_g_rad = rho_known ? wrap_angle(x(kPsi)) : kNaN;
  out.psi_r_rad = wrap_angle(x(kPsi) - rho);
  out.z_g_m = std::sqrt(out.covariance(2, 2)) <= cfg_.max_z_sigma_m ? x(kZ) : kNaN;
  if (std::isfinite(out.rho_g_rad) && std::isfinite(out.z_g_m)) {
    const auto [roll, pitch] = level_at(t_ns);
    out.T_pen_body = T_pen_body(x, roll, pitch);
    out.T_pen_camera = out.T_pen_body * cfg_.T_body_camera;
  }
  return out;
}

GlobalPoseCounters GlobalPoseEstimator::counters() const {
  GlobalPoseCounters c = state_.counts;
  auto merge = [](SensorCounters& dst, const SensorCounters& arrival) {
    dst.received = arrival.received;
    dst.duplicates = arrival.duplicates;
    dst.out_of_order = arrival.out_of_order;
    dst.too_late = arrival.too_late;
    dst.invalid += arrival.invalid;
  };
  merge(c.dvl_velocity, arrival_.dvl_velocity);
  c.dvl_velocity.spikes = dvl_spikes_.spikes();
  c.dvl_velocity.received += c.dvl_velocity.spikes;
  c.dvl_velocity.rejected += c.dvl_velocity.spikes;
  merge(c.depth, arrival_.depth);
  merge(c.attitude, arrival_.attitude);
  merge(c.vision_fix, arrival_.vision_fix);
  return c;
}

void GlobalPoseEstimator::apply(const Event& e) {
  if (state_.initialised) {
    const int64_t t_ns = std::max(e.t_ns, state_.ekf.t_ns);
    state_.ekf.predict_to(t_ns, process_noise(state_.ekf.t_ns, t_ns));
  }
  state_.last_time_ns = std::max(state_.last_time_ns, e.t_ns);
  switch (e.kind) {
    case kAttitude:
      apply_attitude(std::get<AttitudeSample>(e.sample));
      break;
    case kDepth:
      apply_depth(std::get<PressureSample>(e.sample));
      break;
    case kDvl:
      apply_dvl(std::get<DvlSample>(e.sample));
      break;
    case kCamera:
      apply_camera(std::get<NetObservation>(e.sample));
      break;
  }
}

}  // namespace pensight::global_pose
