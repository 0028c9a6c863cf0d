#pragma once
// What the global-pose estimators take besides the dataset's sensor samples (DvlSample,
// PressureSample, AttitudeSample of core/dataset_types.h, fed as read), and what they
// give. Timestamps are integer nanoseconds on the clock shared by all sensors.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/dataset_types.h"
#include "pipeline/fft/net_texture.h"
#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

// One camera frame's output of the FFT net detector: 3D net points in C (one per ROI, NaN where
// a ROI found no net) with their qualities (> 0; empty = all 1), and the net-relative pose
// (NaN when not available) with its quality (FftRelativePose::quality; its variance is divided by
// pose_trust of it), and the net texture odometry's step (net_texture.h).
struct NetObservation {
  int64_t t_ns = 0;
  std::vector<Eigen::Vector3d> points_C;
  std::vector<double> quality;
  double d_net_m = kNaN;
  double psi_net_rad = kNaN;
  double pose_quality = 1.0;
  TextureStep texture;  // the centre ray's net point's move since an earlier frame
};

// The estimates.csv columns this stage fills (NaN where not available), the yaw relative to the
// radial direction, the covariance of (r_g, rho_g, z_g, psi_g), and the full 6-DoF pose in P:
// T_pen_body takes body coordinates to P (translation (r_g cos rho_g, r_g sin rho_g, z_g); rotation
// R_pen_body = Rz(psi_g) Ry(pitch) Rx(roll), roll and pitch from the attitude sensor: interpolated
// at t_ns by the fused estimator, the latest sample in the published baseline, 0 without one), and
// T_pen_camera = T_pen_body * T_body_camera (cam0's sensor.yaml T_BS). Both are all-NaN
// matrices (nan_isometry()) whenever any of r_g, rho_g, z_g or psi_g is NaN: before the lock,
// while rho_g is not observable, without a pressure sensor.
struct GlobalPose {
  int64_t t_ns = 0;
  double r_g_m = kNaN;
  double rho_g_rad = kNaN;
  double z_g_m = kNaN;
  double psi_g_rad = kNaN;
  double psi_r_rad = kNaN;
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Constant(kNaN);
  Eigen::Isometry3d T_pen_body = nan_isometry();
  Eigen::Isometry3d T_pen_camera = nan_isometry();
};

}  // namespace pensight::global_pose
