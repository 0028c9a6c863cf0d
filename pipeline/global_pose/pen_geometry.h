#pragma once
// Frames and geometry of a cylindrical net pen, as in ../shared/dataset-format.md: pen frame P
// with z down and the origin on the pen axis at the surface, body frame B forward-right-down,
// attitude as roll, pitch, yaw with R_pen_body = Rz(yaw) Ry(pitch) Rx(roll). The "levelled" frame L
// is the body frame with roll and pitch removed (x forward and horizontal, z down), so R_pen_body =
// Rz(yaw) R_L_B.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "core/dataset_types.h"
#include "core/units.h"

namespace pensight::global_pose {

// R_L_B: takes body-frame vectors to the levelled frame.
Eigen::Matrix3d rotation_level_body(double roll_rad, double pitch_rad);

// An isometry whose 4x4 matrix is all NaN: a pose that is not known.
inline Eigen::Isometry3d nan_isometry() {
  Eigen::Isometry3d T;
  T.matrix().setConstant(kNaN);
  return T;
}

// The body pose in P from the global pose's cylindrical coordinates (r, rho, z), its yaw psi and
// the attitude's roll and pitch; nan_isometry() when any of them is not finite.
Eigen::Isometry3d T_pen_body_cylindrical(double r_m, double rho_rad, double z_m, double psi_rad,
                                         double roll_rad, double pitch_rad);

// Distance along the unit direction `dir_pen` from `origin_pen` (inside the pen) to the vertical
// cylinder x^2 + y^2 = radius^2; nullopt when the ray is vertical or starts outside.
std::optional<double> ray_to_cylinder(const Eigen::Vector3d& origin_pen,
                                      const Eigen::Vector3d& dir_pen, double radius_m);

// The net wall the vehicle works at, in P: the vertical cylinder of `radius_m` about the pen axis,
// or a flat panel, the vertical plane through `plane_point_m` with the horizontal unit normal
// `plane_normal` pointing away from the camera side (scene.yaml net_type, dataset-format.md).
// Positions are horizontal (x, y) in P, inside the wall (on the pen axis' side).
struct NetWall {
  double radius_m =
      kDefaultPenRadius_m;  // cylinder; for a flat panel the equivalent cylinder (unused here)
  bool flat = false;
  Eigen::Vector2d plane_point_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d plane_normal = Eigen::Vector2d::UnitX();

  static NetWall cylinder(double radius_m) { return {radius_m}; }
  // `normal` is normalised here; the panel must not pass through the pen frame's origin.
  static NetWall flat_panel(double radius_m, const Eigen::Vector2d& point_m,
                            const Eigen::Vector2d& normal);

  // Distance from `xy` to the wall along its normal: R - |xy|, or n . (p0 - xy).
  double distance_m(const Eigen::Vector2d& xy) const;
  // Bearing in P of the wall's outward normal at the wall point nearest to `xy`: atan2(y, x) on
  // the cylinder, the panel's fixed normal on a flat panel. A heading relative to the wall is
  // psi - normal_bearing_rad (psi_r on the cylinder).
  double normal_bearing_rad(const Eigen::Vector2d& xy) const;
  // How far `to` lies from `from` along the wall's horizontal direction [m]: the arc R times the
  // change of azimuth (wrapped to +-pi) on the cylinder, the move along the panel (positive with
  // increasing azimuth, as on the cylinder) on a flat panel.
  double along_change_m(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;
  // The position at azimuth rho_rad (atan2(y, x) = rho) that lies `distance_m` in front of the
  // wall; nullopt when the azimuth's ray misses the panel there.
  std::optional<Eigen::Vector2d> position_at(double rho_rad, double distance_m) const;
  // Distance along the unit `dir_pen` from `origin_pen` (inside) to the wall; nullopt when the ray
  // is horizontal-parallel to it, points away from it or starts outside.
  std::optional<double> ray_distance(const Eigen::Vector3d& origin_pen,
                                     const Eigen::Vector3d& dir_pen) const;
};

// Net-relative pose of a camera looking at the pen wall: d_net along +z_C to the wall and the
// psi_net / pitch_net angles of the wall normal at that point (conventions of dataset-format.md).
struct NetRelativePose {
  double d_net_m = kNaN;
  double psi_net_rad = kNaN;
  double pitch_net_rad = kNaN;
};
NetRelativePose net_relative_pose(const Eigen::Isometry3d& T_pen_camera, const NetWall& wall);

}  // namespace pensight::global_pose
