#pragma once
// What the global-pose estimators take besides the dataset's sensor samples (DvlSample,
// PressureSample, AttitudeSample of pipeline/dataset/dataset_types.h, fed as read), and what they
// give. Timestamps are integer nanoseconds on the clock shared by all sensors.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pipeline/dataset/dataset_types.h"
#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

// One camera frame's output of the FFT net detector: 3D net points in C (one per ROI, NaN where
// a ROI found no net) with their qualities (> 0; empty = all 1), and the net-relative pose
// (NaN when not available).
struct NetObservation {
  int64_t t_ns = 0;
  std::vector<Eigen::Vector3d> points_C;
  std::vector<double> quality;
  double d_net_m = kNaN;
  double psi_net_rad = kNaN;
};

// The estimates.csv columns this stage fills (NaN where not available), the yaw relative to the
// radial direction, and the covariance of (r_g, rho_g, z_g, psi_g).
struct GlobalPose {
  int64_t t_ns = 0;
  double r_g_m = kNaN;
  double rho_g_rad = kNaN;
  double z_g_m = kNaN;
  double psi_g_rad = kNaN;
  double psi_r_rad = kNaN;
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Constant(kNaN);
};

}  // namespace pensight::global_pose
