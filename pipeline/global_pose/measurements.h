#pragma once
// Timestamped sensor samples fed to the global-pose estimators (dataset-format.md sensors).
// Timestamps are integer nanoseconds on the clock shared by all sensors.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

// dvl0/data.csv: body-frame velocity over the net/ground (already rotated by the DVL's T_BS) and
// optional beam ranges (NaN where a beam has no return).
struct DvlSample {
  int64_t t_ns = 0;
  Eigen::Vector3d v_B_mps = Eigen::Vector3d::Constant(kNaN);
  bool valid = true;
  std::array<double, 4> range_m = {kNaN, kNaN, kNaN, kNaN};
};

// pressure0/data.csv: depth of the body origin, positive down.
struct DepthSample {
  int64_t t_ns = 0;
  double depth_m = kNaN;
};

// imu0/attitude.csv: body attitude. The yaw's origin need not be the pen frame's.
struct AttitudeSample {
  int64_t t_ns = 0;
  double roll_rad = kNaN;
  double pitch_rad = kNaN;
  double yaw_rad = kNaN;
};

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
