#include "pipeline/global_pose/published_global_pose.h"

#include <cmath>
#include <utility>

#include "core/log.h"

namespace pensight::global_pose {

PublishedGlobalPose::PublishedGlobalPose(PublishedGlobalPoseConfig config)
    : cfg_(std::move(config)) {
  validate(cfg_);
  cfg_.circle.radius_m = cfg_.pen_radius_m;
  if (!cfg_.has_dvl)
    log_warning(
        "global pose (published): no DVL, rho_g and psi_g cannot be integrated; they are NaN");
}

void PublishedGlobalPose::add(const DvlSample& s) {
  if (!cfg_.has_dvl) return;
  if (!s.valid || !s.velocity_B_mps.allFinite()) {
    if (!std::exchange(warned_invalid_dvl_, true))
      log_warning("global pose (published): invalid/NaN DVL velocity skipped");
    return;
  }
  const int64_t prev = std::exchange(last_dvl_ns_, s.timestamp_ns);
  if (!started_ || !fix_.ok || prev < 0) return;
  const double dt = seconds_between(prev, s.timestamp_ns);
  if (dt <= 0) return;
  if (dt > cfg_.max_dvl_gap_s) return;
  const Eigen::Vector3d v_L =
      cfg_.level_with_attitude
          ? Eigen::Vector3d(rotation_level_body(roll_rad_, pitch_rad_) * s.velocity_B_mps)
          : s.velocity_B_mps;
  // Direction of increasing rho in L: the outward radial (bearing -psi_r) turned by +90 deg.
  const Eigen::Vector2d e_rho(std::sin(fix_.psi_r_rad), std::cos(fix_.psi_r_rad));
  rho_rad_ += dt * v_L.head<2>().dot(e_rho) / fix_.r_g_m;
}

void PublishedGlobalPose::add(const PressureSample& s) {
  if (std::isfinite(s.depth_m)) depth_m_ = s.depth_m;
}

void PublishedGlobalPose::add(const AttitudeSample& s) {
  if (std::isfinite(s.roll_rad) && std::isfinite(s.pitch_rad)) {
    roll_rad_ = s.roll_rad;
    pitch_rad_ = s.pitch_rad;
  }
}

GlobalPose PublishedGlobalPose::add(const NetObservation& obs) {
  const PenFix fix = pen_fix_from_net_points(
      obs.points_C, cfg_.T_body_camera, cfg_.level_with_attitude ? roll_rad_ : 0.0,
      cfg_.level_with_attitude ? pitch_rad_ : 0.0, cfg_.circle, obs.quality);
  if (fix.ok) {
    fix_ = fix;
    if (!started_) {
      started_ = true;
      rho_rad_ = cfg_.initial_rho_rad;
    }
  }
  GlobalPose out;
  out.t_ns = obs.t_ns;
  out.z_g_m = depth_m_;
  if (!fix_.ok) return out;
  out.r_g_m = fix_.r_g_m;
  out.psi_r_rad = fix_.psi_r_rad;
  if (cfg_.has_dvl) {
    out.rho_g_rad = wrap_angle(rho_rad_);
    out.psi_g_rad = wrap_angle(rho_rad_ + fix_.psi_r_rad);
  }
  // The latest attitude sample's roll and pitch (0 before one) even when the fix assumes them 0:
  // the pose reports the measured attitude.
  out.T_pen_body = T_pen_body_cylindrical(out.r_g_m, out.rho_g_rad, out.z_g_m, out.psi_g_rad,
                                          roll_rad_, pitch_rad_);
  if (out.T_pen_body.matrix().allFinite()) out.T_pen_camera = out.T_pen_body * cfg_.T_body_camera;
  return out;
}

}  // namespace pensight::global_pose
