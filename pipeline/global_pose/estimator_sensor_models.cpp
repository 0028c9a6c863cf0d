// GlobalPoseEstimator, part 2 of 4: the measurement model of each sensor and its update.
#include "pipeline/global_pose/global_pose_estimator.h"

#include <cmath>
#include <cstdio>

#include "core/log.h"
#include "core/pose_trust.h"
#include "core/units.h"

#include "pipeline/global_pose/estimator_detail.h"

namespace pensight::global_pose {
using namespace detail;

std::pair<double, double> GlobalPoseEstimator::level_at(int64_t t_ns) {
  const auto a = attitude_.at(t_ns, cfg_.max_attitude_gap_s);
  if (a) return {a->roll_rad, a->pitch_rad};
  // At start-up the first attitude sample may simply not have arrived yet.
  const bool starting =
      attitude_.empty() && (state_.init_ns == kNever ||
                            seconds_between(state_.init_ns, t_ns) <= cfg_.max_attitude_gap_s);
  if (cfg_.has_attitude && !starting)
    warn_once(kWarnNoAttitudeAt,
              "no attitude sample near a measurement; assuming roll = pitch = 0");
  return {0.0, 0.0};
}

Eigen::Isometry3d GlobalPoseEstimator::T_pen_body(const StateVector& x, double roll,
                                                  double pitch) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_from_rpy(roll, pitch, x(kPsi));
  T.translation() = x.head<3>();
  return T;
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

void GlobalPoseEstimator::apply_camera(const NetObservation& obs) {
  const auto [roll, pitch] = level_at(obs.t_ns);
  SensorCounters& cf = state_.counts.vision_fix;
  const PenFix fix = pen_fix_from_net_points(obs.points_C, cfg_.T_body_camera, roll, pitch,
                                             cfg_.circle, obs.quality);
  if (!fix.ok) {
    ++cf.invalid;
    warn_once(kWarnFixFailed, "no circle fit on a camera frame (too few net points)");
  } else if (!state_.initialised) {
    const LockCheck lock = check_lock_at(fix, cfg_.initial_rho_rad, obs.t_ns);
    if (lock.lockable()) {
      initialise(fix, obs.t_ns);
      ++cf.accepted;
    } else {
      ++cf.not_lockable;
      warn_once(kWarnNotLockable, "circle fit not trusted to initialise (" + lock.reason +
                                      "); waiting for a better one");
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
  apply_texture(obs, roll, pitch);
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
  const double sigma_scale = 1.0 / std::sqrt(pose_trust(obs.pose_quality));
  gated_update<2>(kVisionRel, cr, Eigen::Vector2d(obs.d_net_m, obs.psi_net_rad), model,
                  diag<2>(sigma_scale * Eigen::Vector2d(cfg_.noise.d_net_frac * obs.d_net_m,
                                                        cfg_.noise.psi_net_rad)),
                  {false, true}, kVisionStates);
}

std::optional<Eigen::Vector3d> GlobalPoseEstimator::centre_ray_point(const StateVector& x,
                                                                     const Eigen::Vector3d& ray_C,
                                                                     double roll,
                                                                     double pitch) const {
  const Eigen::Isometry3d T = T_pen_body(x, roll, pitch) * cfg_.T_body_camera;
  const Eigen::Vector3d dir = (T.linear() * ray_C).normalized();
  const auto range = wall_.ray_distance(T.translation(), dir);
  if (!range) return std::nullopt;
  return Eigen::Vector3d(T.translation() + *range * dir);
}

void GlobalPoseEstimator::start_texture_chain(const NetObservation& obs, double roll,
                                              double pitch) {
  FilterState::TextureChain& chain = state_.texture;
  StateVector& x = state_.ekf.x;
  StateMatrix& P = state_.ekf.P;
  const Eigen::Vector3d ray = obs.texture.ray_C;
  const auto hit = centre_ray_point(x, ray, roll, pitch);
  chain.active = hit.has_value();
  if (!hit) return;
  // Reading = the point's along coordinate now, so the offset is 0 and its error is the point's:
  // the offset's covariance row is that of along(point(x)).
  const auto along = [&](const StateVector& xs) {
    const auto p = centre_ray_point(xs, ray, roll, pitch);
    return Eigen::Matrix<double, 1, 1>(p ? wall_.along_change_m(hit->head<2>(), p->head<2>())
                                         : kNaN);
  };
  const Eigen::Matrix<double, 1, kStateDim> J =
      numeric_jacobian<1>(x, along, kPoseStates3D, {false});
  if (!J.allFinite()) {
    chain.active = false;
    return;
  }
  x(kNetTextureOffset) = 0;
  P.row(kNetTextureOffset).setZero();
  P.col(kNetTextureOffset).setZero();
  const Eigen::Matrix<double, 1, kStateDim> JP = J * P;
  P.row(kNetTextureOffset) = JP;
  P.col(kNetTextureOffset) = JP.transpose();
  P(kNetTextureOffset, kNetTextureOffset) = JP.dot(J) + std::pow(cfg_.noise.net_texture_m, 2);
  chain.last_ns = obs.t_ns;
  chain.x = x;
  chain.roll_rad = roll;
  chain.pitch_rad = pitch;
  chain.hit_pen = *hit;
  chain.hit_along_m = 0;
  chain.reading_m = 0;
}

void GlobalPoseEstimator::apply_texture(const NetObservation& obs, double roll, double pitch) {
  FilterState::TextureChain& chain = state_.texture;
  const TextureStep& step = obs.texture;
  if (!cfg_.use_net_texture || !state_.initialised || !step.valid) {
    chain.active = false;
    return;
  }
  SensorCounters& c = state_.counts.net_texture;
  ++c.received;
  if (!std::isfinite(step.moved_bars[0]) || !std::isfinite(step.moved_bars[1]) ||
      !step.bars_C[0].allFinite() || !step.bars_C[1].allFinite() || !step.ray_C.allFinite() ||
      !(step.bars_C[0].norm() > 0) || !(step.bars_C[1].norm() > 0)) {
    ++c.invalid;
    chain.active = false;
    return;
  }
  if (!chain.active || chain.last_ns != step.from_ns) {
    start_texture_chain(obs, roll, pitch);
    ++c.accepted;
    return;
  }
  // Whole bars: those that bring the measured move nearest to a move predicted from the
  // filter's pose at the odometer's last frame (its roll and pitch too) moved on by the latest
  // DVL velocity and the attitude's yaw rate. Not by the filter's own velocity and yaw rate: the
  // odometer corrects those, so a slipped bar would turn into a yaw rate that predicts the next
  // slip. Nor by the filter's pose now: the fixes move its heading by tenths of a degree between
  // frames, centimetres at the net.
  const MeasurementNoise& n = cfg_.noise;
  const double dt = seconds_between(chain.last_ns, obs.t_ns);
  const double window_s = n.net_texture_yaw_rate_window_s;
  const auto rate_now = attitude_.yaw_rate(obs.t_ns, window_s);
  const auto rate_before =
      attitude_.yaw_rate(obs.t_ns - seconds_to_ns_toward_zero(window_s), window_s);
  // In a turn the prediction is too coarse to count bars by: a yaw rate that changed between the
  // last two windows by enough to move the point by the allowed ambiguity over the interval (the
  // sweep's 2.5 rad/s turns; following changes it by hundredths of a rad/s).
  const double range_m = (chain.hit_pen - T_pen_body(chain.x, chain.roll_rad, chain.pitch_rad) *
                                              cfg_.T_body_camera.translation())
                             .norm();
  const double rate_change = rate_now && rate_before ? std::abs(*rate_now - *rate_before) : 0.0;
  if (range_m * rate_change * dt > n.net_texture_max_unwrap_bars * step.bars_C[0].norm()) {
    ++c.invalid;
    start_texture_chain(obs, roll, pitch);
    return;
  }
  const double yaw_rate = rate_now.value_or(chain.x(kPsiRate));
  const Eigen::Vector3d v_L = state_.last_velocity_L.allFinite()
                                  ? state_.last_velocity_L
                                  : Eigen::Vector3d(chain.x.segment<3>(kU));
  StateVector to = chain.x;
  const double psi_mid = chain.x(kPsi) + 0.5 * dt * yaw_rate;
  to(kX) += dt * (std::cos(psi_mid) * v_L.x() - std::sin(psi_mid) * v_L.y());
  to(kY) += dt * (std::sin(psi_mid) * v_L.x() + std::cos(psi_mid) * v_L.y());
  to(kZ) += dt * v_L.z();
  to(kPsi) = wrap_angle(chain.x(kPsi) + dt * yaw_rate);
  const auto predicted_hit = centre_ray_point(to, step.ray_C, chain.roll_rad, chain.pitch_rad);
  if (!predicted_hit) {
    ++c.invalid;
    chain.active = false;
    return;
  }
  const Eigen::Matrix3d R_pen_camera =
      rotation_from_rpy(chain.roll_rad, chain.pitch_rad, to(kPsi)) * cfg_.T_body_camera.linear();
  Eigen::Matrix<double, 3, 2> bars;
  bars << R_pen_camera * step.bars_C[0], R_pen_camera * step.bars_C[1];
  const Eigen::Vector2d predicted =
      bars.colPivHouseholderQr().solve(*predicted_hit - chain.hit_pen);
  Eigen::Vector2d moved;
  for (int i = 0; i < 2; ++i) {
    const double m = step.moved_bars[static_cast<size_t>(i)];
    const double whole = std::round(predicted(i) - m);
    // Near half a bar either count is as likely: the odometer restarts rather than slip a bar.
    if (std::abs(predicted(i) - m - whole) > n.net_texture_max_unwrap_bars) {
      ++c.invalid;
      start_texture_chain(obs, roll, pitch);
      return;
    }
    moved(i) = m + whole;
  }
  StateVector& x = state_.ekf.x;
  const Eigen::Vector3d measured_hit = chain.hit_pen + bars * moved;
  const double step_m = wall_.along_change_m(chain.hit_pen.head<2>(), measured_hit.head<2>());
  chain.reading_m += step_m;
  state_.ekf.P(kNetTextureOffset, kNetTextureOffset) +=
      std::pow(n.net_texture_step_m, 2) + std::pow(n.net_texture_step_frac * step_m, 2);
  const Eigen::Vector3d from_pen = chain.hit_pen;
  const double from_along = chain.hit_along_m;
  const auto model = [&](const StateVector& xs) {
    const auto p = centre_ray_point(xs, step.ray_C, roll, pitch);
    return Eigen::Matrix<double, 1, 1>(
        p ? from_along + wall_.along_change_m(from_pen.head<2>(), p->head<2>()) -
                xs(kNetTextureOffset)
          : kNaN);
  };
  const UpdateOutcome outcome = gated_update<1>(
      kNetTexture, c, Eigen::Matrix<double, 1, 1>(chain.reading_m), model,
      Eigen::Matrix<double, 1, 1>(n.net_texture_m * n.net_texture_m), {false}, kTextureStates);
  if (outcome != UpdateOutcome::kAccepted) {
    // A slipped bar or a frame that disagrees: the odometer restarts here.
    start_texture_chain(obs, roll, pitch);
    return;
  }
  const auto now = centre_ray_point(x, step.ray_C, roll, pitch);
  if (!now) {
    chain.active = false;
    return;
  }
  chain.hit_along_m += wall_.along_change_m(chain.hit_pen.head<2>(), now->head<2>());
  chain.hit_pen = *now;
  chain.last_ns = obs.t_ns;
  chain.x = x;
  chain.roll_rad = roll;
  chain.pitch_rad = pitch;
}

}  // namespace pensight::global_pose
