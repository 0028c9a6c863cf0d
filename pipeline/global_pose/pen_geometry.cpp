#include "pipeline/global_pose/pen_geometry.h"

#include <cmath>
#include <numbers>

#include "core/net_angles.h"

namespace pensight::global_pose {

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
  T.linear() = rotation_from_rpy(roll_rad, pitch_rad, psi_rad);
  T.translation() = Eigen::Vector3d(r_m * std::cos(rho_rad), r_m * std::sin(rho_rad), z_m);
  return T;
}

std::optional<double> ray_to_cylinder(const Eigen::Vector3d& origin_pen,
                                      const Eigen::Vector3d& dir_pen, double radius_m) {
  const Eigen::Vector2d o = origin_pen.head<2>();
  const Eigen::Vector2d d = dir_pen.head<2>();
  const double a = d.squaredNorm();
  const double c = o.squaredNorm() - radius_m * radius_m;
  if (a < 1e-12 || c > 0) return std::nullopt;
  const double b = o.dot(d);
  // From inside (c <= 0) the far root is the only one ahead of the origin.
  return (-b + std::sqrt(b * b - a * c)) / a;
}

NetWall NetWall::flat_panel(double radius_m, const Eigen::Vector2d& point_m,
                            const Eigen::Vector2d& normal) {
  NetWall w;
  w.radius_m = radius_m;
  w.flat = true;
  w.plane_point_m = point_m;
  w.plane_normal = normal.normalized();
  return w;
}

double NetWall::distance_m(const Eigen::Vector2d& xy) const {
  return flat ? plane_normal.dot(plane_point_m - xy) : radius_m - xy.norm();
}

double NetWall::along_change_m(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
  if (flat) return Eigen::Vector2d(-plane_normal.y(), plane_normal.x()).dot(to - from);
  return radius_m * wrap_angle(std::atan2(to.y(), to.x()) - std::atan2(from.y(), from.x()));
}

double NetWall::normal_bearing_rad(const Eigen::Vector2d& xy) const {
  return flat ? std::atan2(plane_normal.y(), plane_normal.x()) : std::atan2(xy.y(), xy.x());
}

std::optional<Eigen::Vector2d> NetWall::position_at(double rho_rad, double distance_m) const {
  const Eigen::Vector2d u(std::cos(rho_rad), std::sin(rho_rad));
  if (!flat) return Eigen::Vector2d((radius_m - distance_m) * u);
  // n . (p0 - s u) = distance  =>  s = (n . p0 - distance) / (n . u).
  const double nu = plane_normal.dot(u);
  const double s = (plane_normal.dot(plane_point_m) - distance_m) / nu;
  if (!(nu > 1e-9) || !(s >= 0)) return std::nullopt;
  return Eigen::Vector2d(s * u);
}

std::optional<double> NetWall::ray_distance(const Eigen::Vector3d& origin_pen,
                                            const Eigen::Vector3d& dir_pen) const {
  if (!flat) return ray_to_cylinder(origin_pen, dir_pen, radius_m);
  const double ahead = plane_normal.dot(dir_pen.head<2>());
  const double gap = distance_m(origin_pen.head<2>());
  if (!(ahead > 1e-12) || gap < 0) return std::nullopt;
  return gap / ahead;
}

NetRelativePose net_relative_pose(const Eigen::Isometry3d& T_pen_camera, const NetWall& wall) {
  const Eigen::Vector3d axis_pen = T_pen_camera.linear().col(2);
  const auto t = wall.ray_distance(T_pen_camera.translation(), axis_pen);
  if (!t) return {};
  const Eigen::Vector3d hit_pen = T_pen_camera.translation() + *t * axis_pen;
  // The outward wall normal points away from the camera, as m does.
  const double bearing = wall.normal_bearing_rad(hit_pen.head<2>());
  const Eigen::Vector3d normal_pen(std::cos(bearing), std::sin(bearing), 0);
  const Eigen::Vector3d m = T_pen_camera.linear().transpose() * normal_pen;
  const NetAngles angles = net_angles_from_normal_C(m);
  return {*t, angles.psi_rad, angles.pitch_rad};
}

}  // namespace pensight::global_pose
