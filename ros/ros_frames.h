#pragma once
// ROS frames (REP 103) against the dataset contract's (docs/conventions.md, docs/ros.md).
// ROS: world ENU (x east, y north, z up), body FLU (x forward, y left, z up); a sensor_msgs/Imu
// orientation is the rotation R_enu_flu (body FLU -> world ENU).
// pensight: pen frame P with z down, body FRD. P is taken as NED (x north, y east, z down): the
// contract fixes only P's z axis, and the pen's azimuth origin is not observable from the net
// (dataset-format.md, Global pose), so this choice only sets where yaw 0 points.
//   R_pen_body = R_ned_enu * R_enu_flu * R_flu_frd
//   R_ned_enu = [0 1 0; 1 0 0; 0 0 -1] (swap x and y, flip z), R_flu_frd = diag(1, -1, -1).
#include <Eigen/Geometry>

namespace pensight {

// R_pen_body, the body's attitude in P (rpy_from_rotation gives the contract's roll, pitch, yaw),
// from a ROS orientation R_enu_flu. Precondition: q_enu_flu is a unit quaternion.
Eigen::Matrix3d rotation_pen_body_from_ros(const Eigen::Quaterniond& q_enu_flu);

// The inverse: the ROS orientation R_enu_flu of a body attitude R_pen_body (rotation_from_rpy).
Eigen::Quaterniond ros_orientation_from_pen_body(const Eigen::Matrix3d& R_pen_body);

}  // namespace pensight
