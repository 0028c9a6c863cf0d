// GlobalPoseEstimator, part 4 of 4: initialisation from the first lockable vision fix, the
// lock check, and re-initialisation of the position from agreeing gated-out fixes.
#include "pipeline/global_pose/global_pose_estimator.h"

#include <cmath>
#include <cstdio>

#include "core/units.h"

#include "pipeline/global_pose/estimator_detail.h"

namespace pensight::global_pose {
using namespace detail;

std::optional<GlobalPoseEstimator::WallPose> GlobalPoseEstimator::pose_from_fix(
    const WallFix& fix, double rho_rad) const {
  const auto xy = wall_.position_at(rho_rad, fix.z.x());
  if (!xy) return std::nullopt;
  const double bearing = wall_.normal_bearing_rad(*xy);
  return WallPose{*xy, Eigen::Vector2d(std::cos(bearing), std::sin(bearing)), bearing + fix.z.y()};
}

LockCheck GlobalPoseEstimator::check_lock_at(const PenFix& fix, double rho_rad,
                                             int64_t t_ns) const {
  LockCheck check = check_lock(fix, cfg_.lock);
  // An oblique fix within max_abs_psi_r_with_plane_rad locks only where the DVL plane agrees.
  const LockCheck oblique = check;
  const bool needs_plane = check.verdict == LockVerdict::kOblique &&
                           std::abs(fix.psi_r_rad) <= cfg_.lock.max_abs_psi_r_with_plane_rad;
  if (needs_plane) check = {};
  const auto pose = pose_from_fix(wall_fix(fix), rho_rad);
  if (check.lockable() && !pose)
    check = {LockVerdict::kMissesThePanel,
             "the fix puts the vehicle beyond the flat panel's reach at this azimuth"};
  const bool recent_plane =
      state_.plane_ns != kNever &&
      std::abs(seconds_between(state_.plane_ns, t_ns)) <= cfg_.lock.max_plane_age_s;
  if (!check.lockable()) return check;
  if (!recent_plane || !cfg_.dvl_beams) return needs_plane ? oblique : check;
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
  const double age_s = std::abs(seconds_between(state_.plane_ns, t_ns));
  if (!(std::abs(dd) <= cfg_.lock.plane_distance_tol_m + speed * age_s) ||
      !(std::abs(dh) <= cfg_.lock.plane_heading_tol_rad)) {
    char buf[128];
    std::snprintf(buf, sizeof(buf), "DVL net plane disagrees by %.2f m, %.2f rad", dd, dh);
    check = {LockVerdict::kDisagreesWithDvlPlane, buf};
  }
  return check;
}

void GlobalPoseEstimator::reinitialise_position(const PenFix& fix, double distance_rate_mps,
                                                int64_t t_ns) {
  PenEkf& ekf = state_.ekf;
  StateVector& x = ekf.x;
  StateMatrix& P = ekf.P;
  const WallFix wf = wall_fix(fix);
  const auto pose = pose_from_fix(wf, std::atan2(x(kY), x(kX)));
  if (!pose) return;  // check_lock_at refused such a fix before it got here
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
    P(i, i) = std::pow(cfg_.priors.velocity_after_reinit_mps, 2);
  }
  // The attitude yaw's offset was estimated against the wrong heading: set it again from the next
  // attitude sample.
  state_.yaw_bias_set = false;
  state_.consecutive_rejections.fill(0);
  ekf.t_ns = std::max(ekf.t_ns, t_ns);
}

void GlobalPoseEstimator::initialise(const PenFix& fix, int64_t t_ns) {
  const double rho0 = cfg_.initial_rho_rad;
  const FilterPriors& pr = cfg_.priors;
  PenEkf& ekf = state_.ekf;
  ekf.t_ns = t_ns;
  ekf.x.setZero();
  ekf.P.setZero();
  // check_lock_at has checked that the azimuth reaches the wall.
  const auto pose = pose_from_fix(wall_fix(fix), rho0);
  if (!pose) return;
  const Eigen::Vector2d& normal = pose->normal;
  ekf.x.head<2>() = pose->xy_m;
  // rho_g is defined as rho0 here: only the distance to the wall is uncertain.
  ekf.P.topLeftCorner<2, 2>() = fix.covariance(0, 0) * normal * normal.transpose() +
                                std::pow(pr.position_along_wall_m, 2) * Eigen::Matrix2d::Identity();
  const bool depth = std::isfinite(state_.last_depth_m);
  ekf.x(kZ) = depth ? state_.last_depth_m : 0.0;
  ekf.P(kZ, kZ) = std::pow(depth ? cfg_.noise.depth_m : pr.depth_without_pressure_m, 2);
  ekf.x(kPsi) = wrap_angle(pose->psi_rad);
  // The fix's heading carries the vision heading bias (0 expected): psi's error is the bias.
  const double bias_var = std::pow(cfg_.noise.process.fix_heading_bias_rad, 2);
  ekf.P(kPsi, kPsi) = fix.covariance(1, 1) + std::pow(cfg_.noise.fix_psi_r_floor_rad, 2) + bias_var;
  ekf.P(kFixHeadingBias, kFixHeadingBias) = bias_var;
  ekf.P(kPsi, kFixHeadingBias) = ekf.P(kFixHeadingBias, kPsi) = -bias_var;
  const bool velocity = state_.last_velocity_L.allFinite();
  ekf.x.segment<3>(kU) = velocity ? state_.last_velocity_L : Eigen::Vector3d::Zero();
  ekf.P.block<3, 3>(kU, kU) =
      std::pow(velocity ? cfg_.noise.dvl_velocity_mps : pr.velocity_without_dvl_mps, 2) *
      Eigen::Matrix3d::Identity();
  // The vehicle may be turning fast when the first fix comes (a sweep): take the yaw rate from
  // the attitude sensor when it has samples around t.
  const auto yaw_now = attitude_.at(t_ns, cfg_.max_attitude_gap_s);
  const auto yaw_before =
      attitude_.at(t_ns - seconds_to_ns_toward_zero(pr.psi_rate_window_s), cfg_.max_attitude_gap_s);
  if (cfg_.use_attitude_yaw && yaw_now && yaw_before && std::isfinite(yaw_now->yaw_rad) &&
      std::isfinite(yaw_before->yaw_rad) && yaw_now->timestamp_ns != yaw_before->timestamp_ns) {
    ekf.x(kPsiRate) = wrap_angle(yaw_now->yaw_rad - yaw_before->yaw_rad) /
                      seconds_between(yaw_before->timestamp_ns, yaw_now->timestamp_ns);
    ekf.P(kPsiRate, kPsiRate) = std::pow(pr.psi_rate_from_attitude_radps, 2);
  } else {
    ekf.P(kPsiRate, kPsiRate) = std::pow(pr.psi_rate_radps, 2);
  }
  ekf.P(kYawBias, kYawBias) = std::pow(pr.attitude_yaw_offset_rad, 2);
  ekf.P(kDvlBiasU, kDvlBiasU) = ekf.P(kDvlBiasV, kDvlBiasV) =
      std::pow(cfg_.noise.dvl_bias_prior_mps, 2);
  state_.initialised = true;
  state_.yaw_bias_set = false;
  state_.last_rho_aid_ns = t_ns;  // rho_g is rho0 here by definition
  state_.init_ns = t_ns;
}

}  // namespace pensight::global_pose
