#include "pipeline/global_pose/pen_geometry.h"

#include <cmath>
#include <numbers>

namespace pensight::global_pose {

double wrap_angle(double a_rad) {
  if (!std::isfinite(a_rad)) return a_rad;
  double w = std::remainder(a_rad, 2 * std::numbers::pi);
  if (w <= -std::numbers::pi) w += 2 * std::numbers::pi;
  return w;
}

Eigen::Matrix3d rotation_pen_body(double roll_rad, double pitch_rad, double yaw_rad) {
  return (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d rotation_level_body(double roll_rad, double pitch_rad) {
  return (Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d T_pen_body_cylindrical(double r_m, double rho_rad, double z_m, double psi_rad,
                                         double roll_rad, double pitch_rad) {
  for (const double v : {r_m, rho_rad, z_m, psi_rad, roll_rad, pitch_rad})
    if (!std::isfinite(v)) return nan_isometry();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_pen_body(roll_rad, pitch_rad, psi_rad);
  T.translation() = Eigen::Vector3d(r_m * std::cos(rho_rad), r_m * std::sin(rho_rad), z_m);
  return T;
}

std::optional<double> ray_to_cylinder(const Eigen::Vector3d& origin_P, const Eigen::Vector3d& dir_P,
                                      double radius_m) {
  const Eigen::Vector2d o = origin_P.head<2>();
  const Eigen::Vector2d d = dir_P.head<2>();
  const double a = d.squaredNorm();
  const double c = o.squaredNorm() - radius_m * radius_m;
  if (a < 1e-12 || c > 0) return std::nullopt;
  const double b = o.dot(d);
  // From inside (c <= 0) the far root is the only one ahead of the origin.
  return (-b + std::sqrt(b * b - a * c)) / a;
}

NetRelativePose net_relative_pose(const Eigen::Isometry3d& T_pen_camera, double radius_m) {
  const Eigen::Vector3d axis_P = T_pen_camera.linear().col(2);
  const auto t = ray_to_cylinder(T_pen_camera.translation(), axis_P, radius_m);
  if (!t) return {};
  const Eigen::Vector3d hit_P = T_pen_camera.translation() + *t * axis_P;
  // The outward wall normal points away from the camera, as m does.
  const Eigen::Vector3d normal_P(hit_P.x(), hit_P.y(), 0);
  const Eigen::Vector3d m = T_pen_camera.linear().transpose() * normal_P.normalized();
  return {*t, std::atan2(-m.x(), m.z()), std::atan2(-m.y(), m.z())};
}

}  // namespace pensight::global_pose
