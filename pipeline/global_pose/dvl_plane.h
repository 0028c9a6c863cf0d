#pragma once
// The acoustic baseline: the plane through the end points of a forward-looking DVL's beams
// (3 or 4 valid ranges) gives the distance and heading of the vehicle relative to the net, and,
// expressed in the camera frame, a d_net / psi_net / pitch_net comparable with the vision ones.
#include <Eigen/Geometry>
#include <array>

#include "core/dataset_types.h"
#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

struct DvlPlane {
  bool ok = false;
  int beams = 0;
  Eigen::Vector3d normal_B = Eigen::Vector3d::Constant(kNaN);  // unit, away from the vehicle
  double distance_m = kNaN;      // perpendicular, from the body origin to the plane
  double heading_rad = kNaN;     // yaw relative to the net normal, as psi_r (levelled frame)
  double residual_rms_m = kNaN;  // of the beam end points (0 with 3 beams)

  // The plane as the net-relative pose of a camera mounted at T_body_camera.
  NetRelativePose in_camera(const Eigen::Isometry3d& T_body_camera) const;
};

// The DVL's pose and beam directions come from dvl0/sensor.yaml (the directions are normalised on
// use). Non-finite or non-positive ranges are ignored. Roll and pitch (body attitude) level the
// normal before the heading is taken; the distance does not depend on them.
DvlPlane dvl_net_plane(const DvlCalibration& dvl, const std::array<double, 4>& range_m,
                       double roll_rad = 0, double pitch_rad = 0);

// The beam ranges a DVL at T_pen_body would measure on the net wall (NaN where a beam misses).
std::array<double, 4> dvl_ranges_to_wall(const DvlCalibration& dvl,
                                         const Eigen::Isometry3d& T_pen_body, const NetWall& wall);

}  // namespace pensight::global_pose
