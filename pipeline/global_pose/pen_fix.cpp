#include "pipeline/global_pose/pen_fix.h"

#include <cmath>

namespace pensight::global_pose {

std::vector<Eigen::Vector2d> horizontal_net_points(std::span<const Eigen::Vector3d> points_C,
                                                   const Eigen::Isometry3d& T_body_camera,
                                                   double roll_rad, double pitch_rad) {
  const Eigen::Isometry3d T_level_camera =
      Eigen::Isometry3d(rotation_level_body(roll_rad, pitch_rad)) * T_body_camera;
  std::vector<Eigen::Vector2d> out;
  out.reserve(points_C.size());
  for (const auto& p : points_C) out.push_back((T_level_camera * p).head<2>());
  return out;
}

PenFix pen_fix_from_circle(const CircleFit& circle) {
  PenFix fix;
  fix.circle = circle;
  const Eigen::Vector2d c = circle.centre;
  const double r = c.norm();
  if (!circle.ok || !(r > 0)) return fix;
  // The outward radial direction at the body is -c; its bearing in L is rho_g - psi_g = -psi_r.
  fix.r_g_m = r;
  fix.psi_r_rad = -std::atan2(-c.y(), -c.x());
  Eigen::Matrix2d j;
  j.row(0) = c.transpose() / r;
  j.row(1) = Eigen::Vector2d(c.y(), -c.x()).transpose() / (r * r);
  fix.covariance = j * circle.centre_covariance * j.transpose();
  fix.ok = fix.covariance.allFinite();
  return fix;
}

PenFix pen_fix_from_net_points(std::span<const Eigen::Vector3d> points_C,
                               const Eigen::Isometry3d& T_body_camera, double roll_rad,
                               double pitch_rad, const CircleFitOptions& options,
                               std::span<const double> weights) {
  const auto xy = horizontal_net_points(points_C, T_body_camera, roll_rad, pitch_rad);
  return pen_fix_from_circle(fit_circle_known_radius(xy, options, weights));
}

}  // namespace pensight::global_pose
