#include "sim/trajectory.h"

#include <algorithm>
#include <cmath>

namespace pensight::sim {
namespace {

Waypoint interpolate(const std::vector<Waypoint>& w, double t) {
  if (t <= w.front().t_s) return w.front();
  if (t >= w.back().t_s) return w.back();
  const auto hi = std::upper_bound(w.begin(), w.end(), t,
                                   [](double v, const Waypoint& p) { return v < p.t_s; });
  const Waypoint& a = *(hi - 1);
  const Waypoint& b = *hi;
  const double f = (t - a.t_s) / (b.t_s - a.t_s);
  auto mix = [f](double x, double y) { return x + f * (y - x); };
  Waypoint r;
  r.t_s = t;
  r.along_m = mix(a.along_m, b.along_m);
  r.net_distance_m = mix(a.net_distance_m, b.net_distance_m);
  r.depth_m = mix(a.depth_m, b.depth_m);
  r.heading_rad = mix(a.heading_rad, b.heading_rad);
  r.pitch_rad = mix(a.pitch_rad, b.pitch_rad);
  r.roll_rad = mix(a.roll_rad, b.roll_rad);
  return r;
}

double facing_yaw(const PenConfig& pen, double along_m) {
  return pen.shape == NetShape::kCylinder ? along_m / pen.radius_m : 0.0;
}

}  // namespace

Eigen::Vector3d net_point(const PenConfig& pen, double along_m, double net_distance_m,
                          double depth_m) {
  if (pen.shape == NetShape::kPlane) return {pen.radius_m - net_distance_m, along_m, depth_m};
  const double theta = along_m / pen.radius_m, r = pen.radius_m - net_distance_m;
  return {r * std::cos(theta), r * std::sin(theta), depth_m};
}

Eigen::Vector3d outward_normal(const PenConfig& pen, double along_m) {
  const double yaw = facing_yaw(pen, along_m);
  return {std::cos(yaw), std::sin(yaw), 0.0};
}

BodyState body_state(const Scenario& s, double t_s) {
  const double t = s.waypoints.front().t_s + t_s;
  auto pose_at = [&](double time, BodyState& out) {
    const Waypoint w = interpolate(s.waypoints, time);
    out.roll_rad = w.roll_rad;
    out.pitch_rad = w.pitch_rad;
    out.yaw_rad = facing_yaw(s.pen, w.along_m) + w.heading_rad;
    out.T_world_body.setIdentity();
    out.T_world_body.linear() = rotation_from_rpy(out.roll_rad, out.pitch_rad, out.yaw_rad);
    out.T_world_body.translation() = net_point(s.pen, w.along_m, w.net_distance_m, w.depth_m);
  };
  BodyState state, before, after;
  pose_at(t, state);
  // Central difference (one-sided at the first waypoint): exact inside a linear segment, the
  // mean of both sides at a waypoint.
  constexpr double kDt = 1e-4;
  const double t0 = std::max(t - kDt, s.waypoints.front().t_s);
  pose_at(t0, before);
  pose_at(t + kDt, after);
  state.velocity_world_mps =
      (after.T_world_body.translation() - before.T_world_body.translation()) / (t + kDt - t0);
  return state;
}

}  // namespace pensight::sim
