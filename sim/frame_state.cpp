#include "sim/frame_state.h"

#include <cmath>

#include "core/units.h"

namespace pensight::sim {

FrameState frame_state(const Scenario& s, int frame) {
  const double t_s = frame / s.camera.calibration.rate_hz;
  return frame_state_at(s, body_state(s, t_s), frame, t_s);
}

FrameState frame_state_at(const Scenario& s, const BodyState& body, int frame, double t_s) {
  FrameState f;
  f.frame = frame;
  f.t_s = t_s;
  f.timestamp_ns = s.start_time_ns + seconds_to_ns(t_s);
  f.body = body;
  f.T_pen_camera = f.body.T_pen_body * s.camera.calibration.T_body_camera;
  for (const Lamp& l : s.light.lamps) {
    LampPose p;
    p.position_m = f.body.T_pen_body * l.position_B_m;
    p.direction = f.body.T_pen_body.linear() * l.direction_B;
    p.intensity = l.intensity * s.light.lamp_level;
    p.exponent = std::log(0.5) / std::log(std::cos(l.half_angle_rad));
    f.lamps.push_back(p);
  }
  for (const Fish& fish : s.fish) {
    const double along = fish.along_m + fish.speed_mps * f.t_s;
    FishPose p;
    p.centre_m = net_point(s.pen, along, fish.net_distance_m, fish.depth_m);
    const Eigen::Vector3d n = outward_normal(s.pen, along);
    p.axis = Eigen::Vector3d(-n.y(), n.x(), 0) * (fish.speed_mps < 0 ? -1.0 : 1.0);
    p.half_length_m = fish.length_m / 2;
    p.half_thickness_m = fish.thickness_m / 2;
    p.albedo = fish.albedo;
    f.fish.push_back(p);
  }
  return f;
}

}  // namespace pensight::sim
