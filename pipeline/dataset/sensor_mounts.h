#pragma once
// The usual sensor mounts, for the simulator's sensors and for defaults where a recording does not
// say (a ROS bag without its sensors' files): a forward-looking camera or DVL turned by pan and
// tilt, and a Janus DVL's four beams.
#include <Eigen/Geometry>

#include "core/dataset_types.h"

namespace pensight {

// Sensor -> body (T_BS) for a forward-looking sensor at position_B_m (FRD body), turned by pan
// (right) and tilt (down): its z axis along body x, its x along body y, its y along body z.
Eigen::Isometry3d forward_mount(const Eigen::Vector3d& position_B_m, double pan_rad,
                                double tilt_rad);

// A Janus DVL: four beams at 45 + k 90 degrees around its z axis, beam_angle_rad off it.
DvlCalibration janus_dvl_calibration(double rate_hz, const Eigen::Isometry3d& T_body_dvl,
                                     double beam_angle_rad);

}  // namespace pensight
