#pragma once
// Frames and geometry of a cylindrical net pen, as in ../shared/dataset-format.md: pen frame P
// with z down and the origin on the pen axis at the surface, body frame B forward-right-down,
// attitude as roll, pitch, yaw with R_P_B = Rz(yaw) Ry(pitch) Rx(roll). The "levelled" frame L is
// the body frame with roll and pitch removed (x forward and horizontal, z down), so
// R_P_B = Rz(yaw) R_L_B.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "pipeline/dataset/dataset_types.h"

namespace pensight::global_pose {

// Wraps an angle to (-pi, pi].
double wrap_angle(double a_rad);

Eigen::Matrix3d rotation_pen_body(double roll_rad, double pitch_rad, double yaw_rad);
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

// Distance along the unit direction `dir_P` from `origin_P` (inside the pen) to the vertical
// cylinder x^2 + y^2 = radius^2; nullopt when the ray is vertical or starts outside.
std::optional<double> ray_to_cylinder(const Eigen::Vector3d& origin_P, const Eigen::Vector3d& dir_P,
                                      double radius_m);

// Net-relative pose of a camera looking at the pen wall: d_net along +z_C to the wall and the
// psi_net / pitch_net angles of the wall normal at that point (conventions of dataset-format.md).
struct NetRelativePose {
  double d_net_m = kNaN;
  double psi_net_rad = kNaN;
  double pitch_net_rad = kNaN;
};
NetRelativePose net_relative_pose(const Eigen::Isometry3d& T_pen_camera, double radius_m);

}  // namespace pensight::global_pose
