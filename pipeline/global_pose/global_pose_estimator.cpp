#include "pipeline/global_pose/global_pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#include "runtime/error.h"
#include "runtime/log.h"

namespace pensight::global_pose {
namespace {

enum Sensor : int { kDvlVelocity, kDvlPlane, kDepthSensor, kAttitudeYaw, kVisionFix, kVisionRel };

enum Warning : int {
  kWarnNoAttitudeAt,
  kWarnInvalidDvl,
  kWarnInvalidDepth,
  kWarnFixFailed,
  kWarnRejected,
  kWarnRelock,
  kWarnOutOfOrder,
  kWarnDuplicate,
  kWarnTooLate,
  kWarnNotLockable,
  kWarnDvlSpike,
};

const char* sensor_name(int s) {
  static const char* names[] = {"DVL velocity", "DVL plane",        "pressure depth",
                                "attitude yaw", "vision r_g/psi_r", "vision d_net/psi_net"};
  return names[s];
}

// The states each measurement model reads (a vertical cylinder does not depend on depth).
constexpr int kPoseStates[] = {kX, kY, kPsi};
constexpr int kVisionStates[] = {kX, kY, kPsi, kFixHeadingBias};
constexpr int kVelocityStates[] = {kU, kV, kW, kDvlBiasU, kDvlBiasV};
constexpr int kDepthStates[] = {kZ};
constexpr int kYawStates[] = {kPsi, kYawBias};

template <int M>
Eigen::Matrix<double, M, M> diag(const Eigen::Matrix<double, M, 1>& sigma) {
  return sigma.cwiseAbs2().asDiagonal();
}

}  // namespace

std::string describe(const GlobalPoseCounters& c) {
  std::string out;
  const std::pair<const char*, const SensorCounters*> rows[] = {
      {"DVL velocity", &c.dvl_velocity}, {"DVL plane", &c.dvl_plane},
      {"pressure depth", &c.depth},      {"attitude", &c.attitude},
      {"vision fix", &c.vision_fix},     {"vision d_net/psi_net", &c.vision_relative}};
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
  if (!(cfg_.pen_radius_m > 0))
    throw Error(
        "global pose: pen_radius_m must be > 0 (scene.yaml pen_radius_m; 100 for a flat net)");
  if (!(cfg_.history_s >= 0))
    throw Error("global pose: history_s must be >= 0 (seconds of late samples to re-apply)");
  if (cfg_.flat_panel) {
    const Eigen::Vector2d normal = cfg_.flat_panel->plane_normal.head<2>();
    const Eigen::Vector2d point = cfg_.flat_panel->plane_point_m.head<2>();
    if (!(normal.norm() > 0.5) || !(normal.normalized().dot(point) > 0))
      throw Error(
          "global pose: the flat panel's normal must be horizontal and point away from the pen "
          "frame's origin (scene.yaml net_plane_normal, net_plane_point_m)");
    wall_ = NetWall::flat_panel(cfg_.pen_radius_m, point, normal);
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
  // The pen-frame velocity for the spike test: levelled and turned by the attitude (its yaw
  // offset from P cancels in the difference of two samples), else by the filter's heading.
  const auto a = attitude_.at(s.timestamp_ns, cfg_.max_attitude_gap_s);
  const double heading =
      a && std::isfinite(a->yaw_rad) ? a->yaw_rad : (state_.initialised ? state_.ekf.x(kPsi) : 0.0);
  const Eigen::Vector3d v_P =
      rotation_pen_body(a ? a->roll_rad : 0.0, a ? a->pitch_rad : 0.0, heading) * s.velocity_B_mps;
  const int spikes_before = dvl_spikes_.spikes();
  for (const DvlSample& r : dvl_spikes_.push(s, v_P))
    enqueue({r.timestamp_ns, kDvl, r}, arrival_.dvl_velocity);
  if (dvl_spikes_.spikes() > spikes_before)
    warn_once(kWarnDvlSpike, "DVL velocity spike rejected (beyond the vehicle's acceleration)");
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
    const int64_t window_start = state_.last_time_ns - static_cast<int64_t>(cfg_.history_s * 1e9);
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
    while (!history_.empty() && key_less(e, history_.back().event)) {
      state_ = history_.back().before;
      pending_.insert(pending_.begin(), std::move(history_.back().event));
      history_.pop_back();
    }
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
    const int64_t window_start = state_.last_time_ns - static_cast<int64_t>(cfg_.history_s * 1e9);
    while (!history_.empty() && history_.front().event.t_ns < window_start) {
      history_.pop_front();
      history_trimmed_ = true;
    }
    attitude_.trim_before(window_start - static_cast<int64_t>(cfg_.max_attitude_gap_s * 1e9));
  }

  GlobalPose out;
  out.t_ns = t_ns;
  if (!state_.initialised) {
    out.z_g_m = cfg_.has_pressure ? state_.last_depth_m : kNaN;
    return out;
  }
  PenEkf ekf = state_.ekf;
  ekf.predict_to(t_ns, cfg_.noise.process);
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
  const bool rho_aided =
      state_.last_rho_aid_ns != kNever &&
      1e-9 * static_cast<double>(t_ns - state_.last_rho_aid_ns) <= cfg_.max_unaided_s;
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
  if (state_.initialised)
    state_.ekf.predict_to(std::max(e.t_ns, state_.ekf.t_ns), cfg_.noise.process);
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

std::pair<double, double> GlobalPoseEstimator::level_at(int64_t t_ns) {
  const auto a = attitude_.at(t_ns, cfg_.max_attitude_gap_s);
  if (a) return {a->roll_rad, a->pitch_rad};
  // At start-up the first attitude sample may simply not have arrived yet.
  const bool starting = attitude_.empty() && (state_.init_ns == kNever ||
                                              1e-9 * static_cast<double>(t_ns - state_.init_ns) <=
                                                  cfg_.max_attitude_gap_s);
  if (cfg_.has_attitude && !starting)
    warn_once(kWarnNoAttitudeAt,
              "no attitude sample near a measurement; assuming roll = pitch = 0");
  return {0.0, 0.0};
}

Eigen::Isometry3d GlobalPoseEstimator::T_pen_body(const StateVector& x, double roll,
                                                  double pitch) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_pen_body(roll, pitch, x(kPsi));
  T.translation() = x.head<3>();
  return T;
}

template <int M, class H>
UpdateOutcome GlobalPoseEstimator::gated_update(int sensor, SensorCounters& c,
                                                const Eigen::Matrix<double, M, 1>& z, H&& h,
                                                const Eigen::Matrix<double, M, M>& R,
                                                std::array<bool, M> angles,
                                                std::span<const int> depends_on) {
  int& streak = state_.consecutive_rejections[static_cast<size_t>(sensor)];
  const bool motion = sensor == kDvlVelocity || sensor == kAttitudeYaw || sensor == kDepthSensor;
  const bool relock =
      streak >= (motion ? cfg_.motion_relock_after_rejections : cfg_.relock_after_rejections);
  const double gate = cfg_.gate_scale * kGateChi2[M];
  // A motion sensor's sample is first tried with the gate: only one that still fails it after
  // the streak means the motion changed.
  bool ungated = relock && !motion;
  UpdateOutcome outcome = state_.ekf.update<M>(z, h, R, angles, depends_on, ungated ? 0.0 : gate);
  if (relock && motion && outcome == UpdateOutcome::kRejected) {
    release_motion_states(sensor);
    ungated = true;
    outcome = state_.ekf.update<M>(z, h, R, angles, depends_on, 0.0);
  }
  switch (outcome) {
    case UpdateOutcome::kAccepted:
      ++c.accepted;
      if (sensor == kDvlVelocity || sensor == kAttitudeYaw)
        state_.last_rho_aid_ns = state_.ekf.t_ns;
      if (ungated) {
        ++c.relocked;
        warn_once(kWarnRelock, std::string(sensor_name(sensor)) +
                                   " rejected repeatedly; applied without the gate to re-lock");
      }
      streak = 0;
      break;
    case UpdateOutcome::kRejected:
      ++c.rejected;
      ++streak;
      warn_once(kWarnRejected,
                std::string(sensor_name(sensor)) + " sample rejected by the innovation gate");
      break;
    case UpdateOutcome::kSkipped:
      ++c.invalid;
      break;
  }
  return outcome;
}

void GlobalPoseEstimator::release_motion_states(int sensor) {
  // Standard deviations of the released states: above what a vehicle in a pen changes in one
  // sample interval, so the measurement sets them.
  struct Release {
    int state;
    double sigma;
  };
  static constexpr Release kDvlMotion[] = {{kU, 1.0}, {kV, 1.0}, {kW, 1.0}};
  static constexpr Release kYawMotion[] = {{kPsi, 0.2}, {kPsiRate, 1.0}};
  static constexpr Release kDepthMotion[] = {{kZ, 1.0}, {kW, 1.0}};
  StateMatrix& P = state_.ekf.P;
  std::span<const Release> released = kDepthMotion;
  if (sensor == kDvlVelocity) released = kDvlMotion;
  if (sensor == kAttitudeYaw) released = kYawMotion;
  for (const Release& r : released) {
    P.row(r.state).setZero();
    P.col(r.state).setZero();
    P(r.state, r.state) = r.sigma * r.sigma;
  }
}

void GlobalPoseEstimator::apply_attitude(const AttitudeSample& s) {
  SensorCounters& c = state_.counts.attitude;
  if (!cfg_.use_attitude_yaw || !state_.initialised) {
    ++c.accepted;  // its roll and pitch level the other sensors (level_at)
    return;
  }
  if (!std::isfinite(s.yaw_rad)) {
    ++c.invalid;
    return;
  }
  const double var = cfg_.noise.attitude_yaw_rad * cfg_.noise.attitude_yaw_rad;
  if (!state_.yaw_bias_set) {
    // yaw_bias = yaw - psi: its covariance follows psi's.
    StateVector& x = state_.ekf.x;
    StateMatrix& P = state_.ekf.P;
    x(kYawBias) = wrap_angle(s.yaw_rad - x(kPsi));
    P.row(kYawBias) = -P.row(kPsi);
    P.col(kYawBias) = -P.col(kPsi);
    P(kYawBias, kYawBias) = P(kPsi, kPsi) + var;
    state_.yaw_bias_set = true;
    ++c.accepted;
    return;
  }
  gated_update<1>(
      kAttitudeYaw, c, Eigen::Matrix<double, 1, 1>(s.yaw_rad),
      [](const StateVector& x) {
        return Eigen::Matrix<double, 1, 1>(wrap_angle(x(kPsi) + x(kYawBias)));
      },
      Eigen::Matrix<double, 1, 1>(var), {true}, kYawStates);
}

void GlobalPoseEstimator::apply_depth(const PressureSample& s) {
  SensorCounters& c = state_.counts.depth;
  if (!std::isfinite(s.depth_m)) {
    ++c.invalid;
    warn_once(kWarnInvalidDepth, "NaN pressure depth skipped");
    return;
  }
  state_.last_depth_m = s.depth_m;
  if (!state_.initialised) {
    ++c.accepted;
    return;
  }
  const double sd = cfg_.noise.depth_m;
  gated_update<1>(
      kDepthSensor, c, Eigen::Matrix<double, 1, 1>(s.depth_m),
      [](const StateVector& x) { return Eigen::Matrix<double, 1, 1>(x(kZ)); },
      Eigen::Matrix<double, 1, 1>(sd * sd), {false}, kDepthStates);
}

void GlobalPoseEstimator::apply_dvl(const DvlSample& s) {
  const auto [roll, pitch] = level_at(s.timestamp_ns);
  SensorCounters& cv = state_.counts.dvl_velocity;
  if (!s.valid || !s.velocity_B_mps.allFinite()) {
    ++cv.invalid;
    warn_once(kWarnInvalidDvl, "invalid or NaN DVL velocity skipped");
  } else {
    const Eigen::Vector3d v_L = rotation_level_body(roll, pitch) * s.velocity_B_mps;
    state_.last_velocity_L = v_L;
    if (!state_.initialised) {
      ++cv.accepted;
    } else {
      gated_update<3>(
          kDvlVelocity, cv, v_L,
          [](const StateVector& x) {
            return Eigen::Vector3d(x(kU) + x(kDvlBiasU), x(kV) + x(kDvlBiasV), x(kW));
          },
          diag<3>(Eigen::Vector3d::Constant(cfg_.noise.dvl_velocity_mps)), {false, false, false},
          kVelocityStates);
    }
  }
  if (!cfg_.use_dvl_plane || !cfg_.dvl_beams) return;
  const DvlPlane measured = dvl_net_plane(*cfg_.dvl_beams, s.beam_range_m, roll, pitch);
  if (measured.beams == 0) return;  // no ranges in this sample
  SensorCounters& cp = state_.counts.dvl_plane;
  ++cp.received;
  if (!measured.ok) {
    ++cp.invalid;
    return;
  }
  state_.plane_ns = s.timestamp_ns;
  state_.plane_sample = s;
  state_.plane_roll_rad = roll;
  state_.plane_pitch_rad = pitch;
  state_.plane = measured;
  if (!state_.initialised) {
    ++cp.accepted;  // kept to check the first fix against
    return;
  }
  const auto model = [&, roll = roll, pitch = pitch](const StateVector& x) {
    return predicted_plane(x, s, roll, pitch);
  };
  gated_update<2>(
      kDvlPlane, cp, Eigen::Vector2d(measured.distance_m, measured.heading_rad), model,
      diag<2>(Eigen::Vector2d(cfg_.noise.dvl_plane_distance_m, cfg_.noise.dvl_plane_heading_rad)),
      {false, true}, kPoseStates);
}

Eigen::Vector2d GlobalPoseEstimator::predicted_plane(const StateVector& x, const DvlSample& s,
                                                     double roll, double pitch) const {
  // The same beams and the same plane fit as the measurement, so the chord-vs-curve difference of
  // a plane through a curved wall is in the model, not in the innovation.
  auto ranges = dvl_ranges_to_wall(*cfg_.dvl_beams, T_pen_body(x, roll, pitch), wall_);
  for (size_t i = 0; i < 4; ++i)
    if (!std::isfinite(s.beam_range_m[i])) ranges[i] = kNaN;
  const DvlPlane p = dvl_net_plane(*cfg_.dvl_beams, ranges, roll, pitch);
  return {p.distance_m, p.heading_rad};
}

GlobalPoseEstimator::WallFix GlobalPoseEstimator::wall_fix(const PenFix& fix) const {
  // The fitted circle's radius less r_g is the distance to the net along the outward normal,
  // whose bearing in L is -psi_r; on a flat panel the circle stands in for the line. The
  // distance falls as r_g grows, so their covariance with psi_r changes sign.
  WallFix w{{cfg_.circle.radius_m - fix.r_g_m, fix.psi_r_rad}, fix.covariance};
  w.covariance(0, 1) = w.covariance(1, 0) = -fix.covariance(0, 1);
  return w;
}

std::optional<GlobalPoseEstimator::WallPose> GlobalPoseEstimator::pose_from_fix(
    const WallFix& fix, double rho_rad) const {
  const auto xy = wall_.position_at(rho_rad, fix.z.x());
  if (!xy) return std::nullopt;
  const double bearing = wall_.normal_bearing_rad(*xy);
  return WallPose{*xy, Eigen::Vector2d(std::cos(bearing), std::sin(bearing)), bearing + fix.z.y()};
}

std::string GlobalPoseEstimator::lock_refusal_at(const PenFix& fix, double rho_rad,
                                                 int64_t t_ns) const {
  std::string why = lock_refusal(fix, cfg_.lock);
  const auto pose = pose_from_fix(wall_fix(fix), rho_rad);
  if (why.empty() && !pose)
    why = "the fix puts the vehicle beyond the flat panel's reach at this azimuth";
  const bool recent_plane =
      state_.plane_ns != kNever &&
      1e-9 * static_cast<double>(std::abs(t_ns - state_.plane_ns)) <= cfg_.lock.max_plane_age_s;
  if (!why.empty() || !recent_plane || !cfg_.dvl_beams) return why;
  StateVector x = StateVector::Zero();
  x.head<2>() = pose->xy_m;
  x(kPsi) = pose->psi_rad;
  const Eigen::Vector2d p =
      predicted_plane(x, state_.plane_sample, state_.plane_roll_rad, state_.plane_pitch_rad);
  const double dd = p.x() - state_.plane.distance_m;
  const double dh = wrap_angle(p.y() - state_.plane.heading_rad);
  // The plane is up to max_plane_age_s older than the fix: allow for the motion since.
  const double speed =
      state_.last_velocity_L.allFinite() ? state_.last_velocity_L.head<2>().norm() : 0.0;
  const double age_s = 1e-9 * static_cast<double>(std::abs(t_ns - state_.plane_ns));
  if (!(std::abs(dd) <= cfg_.lock.plane_distance_tol_m + speed * age_s) ||
      !(std::abs(dh) <= cfg_.lock.plane_heading_tol_rad)) {
    char buf[128];
    std::snprintf(buf, sizeof(buf), "DVL net plane disagrees by %.2f m, %.2f rad", dd, dh);
    why = buf;
  }
  return why;
}

void GlobalPoseEstimator::apply_camera(const NetObservation& obs) {
  const auto [roll, pitch] = level_at(obs.t_ns);
  SensorCounters& cf = state_.counts.vision_fix;
  const PenFix fix = pen_fix_from_net_points(obs.points_C, cfg_.T_body_camera, roll, pitch,
                                             cfg_.circle, obs.quality);
  if (!fix.ok) {
    ++cf.invalid;
    warn_once(kWarnFixFailed, "no circle fit on a camera frame (too few net points)");
  } else if (!state_.initialised) {
    const std::string why = lock_refusal_at(fix, cfg_.initial_rho_rad, obs.t_ns);
    if (why.empty()) {
      initialise(fix, obs.t_ns);
      ++cf.accepted;
    } else {
      ++cf.not_lockable;
      warn_once(kWarnNotLockable,
                "circle fit not trusted to initialise (" + why + "); waiting for a better one");
    }
    return;
  } else {
    const MeasurementNoise& n = cfg_.noise;
    const WallFix wf = wall_fix(fix);
    Eigen::Matrix2d R = n.fix_inflation * n.fix_inflation * wf.covariance;
    R(0, 0) += n.fix_r_floor_m * n.fix_r_floor_m;
    R(1, 1) += n.fix_psi_r_floor_rad * n.fix_psi_r_floor_rad;
    const auto model = [this](const StateVector& x) {
      const Eigen::Vector2d xy = x.head<2>();
      return Eigen::Vector2d(
          wall_.distance_m(xy),
          wrap_angle(x(kPsi) - wall_.normal_bearing_rad(xy) + x(kFixHeadingBias)));
    };
    const Eigen::Vector2d& z = wf.z;
    if (gated_update<2>(kVisionFix, cf, z, model, R, {false, true}, kVisionStates) ==
        UpdateOutcome::kRejected) {
      const Eigen::Vector2d h = model(state_.ekf.x);
      consider_reinitialising(fix, Eigen::Vector2d(z.x() - h.x(), wrap_angle(z.y() - h.y())),
                              obs.t_ns);
    } else {
      state_.rejected_fixes.clear();
    }
  }
  // Before the lock (a frame without a circle fit) d_net / psi_net have no state to correct and
  // are not counted, like the frames whose fix was not lockable.
  if (!cfg_.use_vision_relative || !state_.initialised) return;
  if (!std::isfinite(obs.d_net_m) && !std::isfinite(obs.psi_net_rad)) return;
  SensorCounters& cr = state_.counts.vision_relative;
  ++cr.received;
  if (!(obs.d_net_m > 0) || !std::isfinite(obs.psi_net_rad)) {
    ++cr.invalid;
    return;
  }
  const auto model = [&, roll = roll, pitch = pitch](const StateVector& x) {
    const NetRelativePose p =
        net_relative_pose(T_pen_body(x, roll, pitch) * cfg_.T_body_camera, wall_);
    return Eigen::Vector2d(p.d_net_m, wrap_angle(p.psi_net_rad + x(kFixHeadingBias)));
  };
  gated_update<2>(
      kVisionRel, cr, Eigen::Vector2d(obs.d_net_m, obs.psi_net_rad), model,
      diag<2>(Eigen::Vector2d(cfg_.noise.d_net_frac * obs.d_net_m, cfg_.noise.psi_net_rad)),
      {false, true}, kVisionStates);
}

void GlobalPoseEstimator::consider_reinitialising(const PenFix& fix,
                                                  const Eigen::Vector2d& innovation, int64_t t_ns) {
  auto& run = state_.rejected_fixes;
  const size_t needed = static_cast<size_t>(std::max(0, cfg_.lock.reinit_after_rejected_fixes));
  const double rho = std::atan2(state_.ekf.x(kY), state_.ekf.x(kX));
  if (needed < 2 || !lock_refusal_at(fix, rho, t_ns).empty()) {
    run.clear();
    return;
  }
  run.push_back({t_ns, innovation});
  if (run.size() > needed) run.erase(run.begin());
  if (run.size() < needed) return;
  // The fixes agree when their innovations lie on a line in time: a constant offset (the filter's
  // position is wrong) plus a constant rate (its velocity is wrong too, e.g. after a reversal the
  // constant-velocity model did not expect).
  double t_mean = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    t_mean += 1e-9 * static_cast<double>(f.t_ns - t_ns);
    mean += f.innovation;
  }
  t_mean /= static_cast<double>(run.size());
  mean /= static_cast<double>(run.size());
  double stt = 0;
  Eigen::Vector2d sty = Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    const double dt = 1e-9 * static_cast<double>(f.t_ns - t_ns) - t_mean;
    stt += dt * dt;
    sty += dt * (f.innovation - mean);
  }
  const Eigen::Vector2d rate = stt > 0 ? Eigen::Vector2d(sty / stt) : Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    const double dt = 1e-9 * static_cast<double>(f.t_ns - t_ns) - t_mean;
    const Eigen::Vector2d residual = f.innovation - mean - dt * rate;
    if (std::abs(residual.x()) > cfg_.lock.agree_r_m ||
        std::abs(residual.y()) > cfg_.lock.agree_psi_r_rad)
      return;
  }
  char buf[240];
  std::snprintf(
      buf, sizeof(buf),
      "global pose: %zu vision fixes in a row gated out but agreeing (distance to the net "
      "off by %.2f m changing %.2f m/s, heading by %.1f deg): position re-initialised at "
      "t = %lld ns",
      run.size(), innovation.x(), rate.x(), innovation.y() * 180.0 / std::numbers::pi,
      static_cast<long long>(t_ns));
  log_warning(buf);
  reinitialise_position(fix, rate.x(), t_ns);
  ++state_.counts.vision_fix.reinitialised;
  run.clear();
}

void GlobalPoseEstimator::reinitialise_position(const PenFix& fix, double distance_rate_mps,
                                                int64_t t_ns) {
  PenEkf& ekf = state_.ekf;
  StateVector& x = ekf.x;
  StateMatrix& P = ekf.P;
  const WallFix wf = wall_fix(fix);
  const auto pose = pose_from_fix(wf, std::atan2(x(kY), x(kX)));
  if (!pose) return;  // lock_refusal_at refused such a fix before it got here
  const Eigen::Vector2d& normal = pose->normal;
  const Eigen::Vector2d along(-normal.y(), normal.x());
  // The position along the wall keeps its uncertainty (the DVL and the attitude yaw carried it);
  // the distance to the wall and the heading restart from the fix, uncorrelated with the rest.
  const double along_var = along.dot(P.topLeftCorner<2, 2>() * along);
  // The cylinder's normal turns with the azimuth, a flat panel's does not.
  const double bearing_var = wall_.flat ? 0.0 : along_var / pose->xy_m.squaredNorm();
  for (const int i : {static_cast<int>(kX), static_cast<int>(kY), static_cast<int>(kPsi)}) {
    P.row(i).setZero();
    P.col(i).setZero();
  }
  x.head<2>() = pose->xy_m;
  P.topLeftCorner<2, 2>() =
      fix.covariance(0, 0) * normal * normal.transpose() + along_var * along * along.transpose();
  // The fix's heading carries the vision heading bias: psi's error is minus the bias' error.
  x(kPsi) = wrap_angle(pose->psi_rad - x(kFixHeadingBias));
  const double bias_var = P(kFixHeadingBias, kFixHeadingBias);
  P(kPsi, kPsi) =
      fix.covariance(1, 1) + std::pow(cfg_.noise.fix_psi_r_floor_rad, 2) + bearing_var + bias_var;
  P(kPsi, kFixHeadingBias) = P(kFixHeadingBias, kPsi) = -bias_var;
  // The fixes' distance changed faster than the filter's by distance_rate_mps: the vehicle moves
  // towards the net by that much more, along the outward normal, whose bearing in the levelled
  // frame is -psi_r. The DVL sets it from a wide prior.
  const Eigen::Vector2d normal_L(std::cos(wf.z.y()), -std::sin(wf.z.y()));
  x.segment<2>(kU) -= distance_rate_mps * normal_L;
  for (const int i : {static_cast<int>(kU), static_cast<int>(kV)}) {
    P.row(i).setZero();
    P.col(i).setZero();
    P(i, i) = 0.3 * 0.3;
  }
  // The attitude yaw's offset was estimated against the wrong heading: set it again from the next
  // attitude sample.
  state_.yaw_bias_set = false;
  state_.consecutive_rejections.fill(0);
  ekf.t_ns = std::max(ekf.t_ns, t_ns);
}

void GlobalPoseEstimator::initialise(const PenFix& fix, int64_t t_ns) {
  const double rho0 = cfg_.initial_rho_rad;
  PenEkf& ekf = state_.ekf;
  ekf.t_ns = t_ns;
  ekf.x.setZero();
  ekf.P.setZero();
  // lock_refusal_at has checked that the azimuth reaches the wall.
  const auto pose = pose_from_fix(wall_fix(fix), rho0);
  if (!pose) return;
  const Eigen::Vector2d& normal = pose->normal;
  ekf.x.head<2>() = pose->xy_m;
  // rho_g is defined as rho0 here: only the distance to the wall is uncertain.
  ekf.P.topLeftCorner<2, 2>() =
      fix.covariance(0, 0) * normal * normal.transpose() + 1e-8 * Eigen::Matrix2d::Identity();
  const bool depth = std::isfinite(state_.last_depth_m);
  ekf.x(kZ) = depth ? state_.last_depth_m : 0.0;
  ekf.P(kZ, kZ) = depth ? std::pow(cfg_.noise.depth_m, 2) : 1e4;
  ekf.x(kPsi) = wrap_angle(pose->psi_rad);
  // The fix's heading carries the vision heading bias (0 expected): psi's error is the bias.
  const double bias_var = std::pow(cfg_.noise.process.fix_heading_bias_rad, 2);
  ekf.P(kPsi, kPsi) = fix.covariance(1, 1) + std::pow(cfg_.noise.fix_psi_r_floor_rad, 2) + bias_var;
  ekf.P(kFixHeadingBias, kFixHeadingBias) = bias_var;
  ekf.P(kPsi, kFixHeadingBias) = ekf.P(kFixHeadingBias, kPsi) = -bias_var;
  const bool velocity = state_.last_velocity_L.allFinite();
  ekf.x.segment<3>(kU) = velocity ? state_.last_velocity_L : Eigen::Vector3d::Zero();
  ekf.P.block<3, 3>(kU, kU) =
      (velocity ? std::pow(cfg_.noise.dvl_velocity_mps, 2) : 0.25) * Eigen::Matrix3d::Identity();
  // The vehicle may be turning fast when the first fix comes (a sweep): take the yaw rate from
  // the attitude sensor when it has samples around t.
  const auto yaw_now = attitude_.at(t_ns, cfg_.max_attitude_gap_s);
  const auto yaw_before = attitude_.at(t_ns - 100'000'000, cfg_.max_attitude_gap_s);
  if (cfg_.use_attitude_yaw && yaw_now && yaw_before && std::isfinite(yaw_now->yaw_rad) &&
      std::isfinite(yaw_before->yaw_rad) && yaw_now->timestamp_ns != yaw_before->timestamp_ns) {
    ekf.x(kPsiRate) =
        wrap_angle(yaw_now->yaw_rad - yaw_before->yaw_rad) /
        (1e-9 * static_cast<double>(yaw_now->timestamp_ns - yaw_before->timestamp_ns));
    ekf.P(kPsiRate, kPsiRate) = 0.1 * 0.1;
  } else {
    ekf.P(kPsiRate, kPsiRate) = 1.0;
  }
  ekf.P(kYawBias, kYawBias) = 10.0;  // set from the first attitude sample
  ekf.P(kDvlBiasU, kDvlBiasU) = ekf.P(kDvlBiasV, kDvlBiasV) =
      std::pow(cfg_.noise.dvl_bias_prior_mps, 2);
  state_.initialised = true;
  state_.yaw_bias_set = false;
  state_.last_rho_aid_ns = t_ns;  // rho_g is rho0 here by definition
  state_.init_ns = t_ns;
}

}  // namespace pensight::global_pose
