#include "ros/ros_frames.h"

namespace pensight {
namespace {

// ENU -> NED coordinates: x and y swap, z flips. Its own inverse.
Eigen::Matrix3d R_ned_enu() {
  Eigen::Matrix3d R;
  R << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return R;
}

// FRD -> FLU coordinates: y and z flip. Its own inverse.
Eigen::Matrix3d R_flu_frd() {
  return Eigen::Vector3d(1, -1, -1).asDiagonal();
}

}  // namespace

Eigen::Matrix3d rotation_pen_body_from_ros(const Eigen::Quaterniond& q_enu_flu) {
  return R_ned_enu() * q_enu_flu.toRotationMatrix() * R_flu_frd();
}

Eigen::Quaterniond ros_orientation_from_pen_body(const Eigen::Matrix3d& R_pen_body) {
  // R_enu_ned = R_ned_enu and R_frd_flu = R_flu_frd (both are their own inverses).
  return Eigen::Quaterniond(R_ned_enu() * R_pen_body * R_flu_frd());
}

}  // namespace pensight
