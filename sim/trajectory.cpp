#include "sim/trajectory.h"

#include <algorithm>
#include <cmath>

namespace pensight::sim {
namespace {

// Shape-preserving cubic Hermite (Fritsch-Carlson) per channel, because linear segments jump the
// velocity at every waypoint: no vehicle does that, and a DVL would report the jump as a spike.
// The curve never overshoots the waypoints (a camera inside its allowed range stays there), stops
// at local extrema, and keeps constant-rate segments exactly linear.
double hermite_slope(const std::vector<Waypoint>& w, size_t k, double Waypoint::*y) {
  auto secant = [&](size_t i) { return (w[i + 1].*y - w[i].*y) / (w[i + 1].t_s - w[i].t_s); };
  if (k == 0) return secant(0);
  if (k + 1 == w.size()) return secant(k - 1);
  const double d0 = secant(k - 1), d1 = secant(k);
  if (d0 * d1 <= 0) return 0.0;
  const double h0 = w[k].t_s - w[k - 1].t_s, h1 = w[k + 1].t_s - w[k].t_s;
  const double a = 2 * h1 + h0, b = h1 + 2 * h0;
  return (a + b) / (a / d0 + b / d1);
}

Waypoint interpolate(const std::vector<Waypoint>& w, double t) {
  if (t <= w.front().t_s) return w.front();
  if (t >= w.back().t_s) return w.back();
  const auto hi = std::upper_bound(w.begin(), w.end(), t,
                                   [](double v, const Waypoint& p) { return v < p.t_s; });
  const size_t k = static_cast<size_t>(hi - w.begin()) - 1;
  const double h = w[k + 1].t_s - w[k].t_s, f = (t - w[k].t_s) / h;
  const double h00 = (1 + 2 * f) * (1 - f) * (1 - f), h10 = f * (1 - f) * (1 - f);
  const double h01 = f * f * (3 - 2 * f), h11 = f * f * (f - 1);
  auto curve = [&](double Waypoint::*y) {
    return h00 * w[k].*y + h10 * h * hermite_slope(w, k, y) + h01 * w[k + 1].*y +
           h11 * h * hermite_slope(w, k + 1, y);
  };
  Waypoint r;
  r.t_s = t;
  r.along_m = curve(&Waypoint::along_m);
  r.net_distance_m = curve(&Waypoint::net_distance_m);
  r.depth_m = curve(&Waypoint::depth_m);
  r.heading_rad = curve(&Waypoint::heading_rad);
  r.pitch_rad = curve(&Waypoint::pitch_rad);
  r.roll_rad = curve(&Waypoint::roll_rad);
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
    out.T_pen_body.setIdentity();
    out.T_pen_body.linear() = rotation_from_rpy(out.roll_rad, out.pitch_rad, out.yaw_rad);
    out.T_pen_body.translation() = net_point(s.pen, w.along_m, w.net_distance_m, w.depth_m);
  };
  BodyState state, before, after;
  pose_at(t, state);
  // Central difference (one-sided at the first waypoint) of the C1 curve.
  constexpr double kDt = 1e-4;
  const double t0 = std::max(t - kDt, s.waypoints.front().t_s);
  pose_at(t0, before);
  pose_at(t + kDt, after);
  state.velocity_pen_mps =
      (after.T_pen_body.translation() - before.T_pen_body.translation()) / (t + kDt - t0);
  const Eigen::AngleAxisd turn(before.T_pen_body.linear().transpose() * after.T_pen_body.linear());
  state.angular_velocity_body_radps = turn.axis() * turn.angle() / (t + kDt - t0);
  return state;
}

}  // namespace pensight::sim
