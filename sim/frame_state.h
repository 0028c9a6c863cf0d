#pragma once
// What changes from frame to frame: the vehicle and camera pose, the lamps and the fish.
#include <Eigen/Geometry>
#include <vector>

#include "sim/scenario.h"
#include "sim/trajectory.h"

namespace pensight::sim {

struct FishPose {
  Eigen::Vector3d centre_m;  // in P
  Eigen::Vector3d axis;      // unit, head direction
  double half_length_m = 0, half_thickness_m = 0, albedo = 0;
};

struct LampPose {
  Eigen::Vector3d position_m, direction;  // in P
  double intensity = 0;                   // dimmer applied
  double exponent = 1;                    // cos^exponent spot fall-off, 1/2 at the half angle
};

struct FrameState {
  int frame = 0;
  double t_s = 0;
  int64_t timestamp_ns = 0;
  BodyState body;
  Eigen::Isometry3d T_pen_camera = Eigen::Isometry3d::Identity();
  std::vector<LampPose> lamps;
  std::vector<FishPose> fish;
};

// Frame `frame` of the scenario's own trajectory.
FrameState frame_state(const Scenario& s, int frame);
// The same for a pose from elsewhere (a closed loop driving the vehicle): `frame` seeds the
// per-frame noise and marine snow, `t_s` (since the start) moves the fish and the timestamp.
FrameState frame_state_at(const Scenario& s, const BodyState& body, int frame, double t_s);

}  // namespace pensight::sim
