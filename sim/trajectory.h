#pragma once
// The vehicle's motion: waypoints in net coordinates (see Waypoint) interpolated in time by a
// shape-preserving cubic (continuous velocity) and turned into body poses in the pen frame P.
#include <Eigen/Geometry>

#include "sim/scenario.h"

namespace pensight::sim {

struct BodyState {
  Eigen::Isometry3d T_pen_body = Eigen::Isometry3d::Identity();
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;
  Eigen::Vector3d velocity_pen_mps = Eigen::Vector3d::Zero();
  // In the body frame: d/dt R_pen_body = R_pen_body [w]x (motion blur, sim/optics.h).
  Eigen::Vector3d angular_velocity_body_radps = Eigen::Vector3d::Zero();
};

// Position in P of a point `net_distance_m` in front of the undeformed net at (along, depth),
// and the outward net normal there (horizontal).
Eigen::Vector3d net_point(const PenConfig& pen, double along_m, double net_distance_m,
                          double depth_m);
Eigen::Vector3d outward_normal(const PenConfig& pen, double along_m);

// Body state at time t_s after the start (clamped to the waypoints' time span).
BodyState body_state(const Scenario& s, double t_s);

}  // namespace pensight::sim
