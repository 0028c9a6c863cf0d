#pragma once
// The published global-pose fix: net points seen by the camera, moved to the body frame, levelled
// (roll and pitch zero, the published assumption, or from the attitude sensor), projected on the
// horizontal plane and fitted with a circle of the pen's known radius. The circle centre c in the
// levelled frame gives the radial distance of the body origin r_g = |c| and the yaw relative to
// the outward radial direction psi_r (dataset-format.md: psi_r = psi_g - rho_g).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>
#include <vector>

#include "pipeline/global_pose/circle_fit.h"

namespace pensight::global_pose {

struct PenFix {
  bool ok = false;
  double r_g_m = kNaN;
  double psi_r_rad = kNaN;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Constant(kNaN);  // of (r_g, psi_r)
  CircleFit circle;
};

// Net points in the camera frame C -> horizontal coordinates (x, y) in the levelled frame L.
// Non-finite points stay non-finite (the circle fit skips them).
std::vector<Eigen::Vector2d> horizontal_net_points(std::span<const Eigen::Vector3d> points_C,
                                                   const Eigen::Isometry3d& T_body_camera,
                                                   double roll_rad = 0, double pitch_rad = 0);

// r_g and psi_r from a circle centre expressed in the levelled frame, with covariance.
PenFix pen_fix_from_circle(const CircleFit& circle);

// The whole fix. `weights` as in fit_circle_known_radius (e.g. FFT ROI qualities).
PenFix pen_fix_from_net_points(std::span<const Eigen::Vector3d> points_C,
                               const Eigen::Isometry3d& T_body_camera, double roll_rad,
                               double pitch_rad, const CircleFitOptions& options,
                               std::span<const double> weights = {});

}  // namespace pensight::global_pose
