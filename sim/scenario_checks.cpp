// validate(Scenario): the checks that need the trajectory and the net geometry.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.h"
#include "sim/net_geometry.h"
#include "sim/scenario.h"
#include "sim/trajectory.h"

namespace pensight::sim {
namespace {

std::string at_time(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f s", t);
  return buf;
}

}  // namespace

void validate(const Scenario& s) {
  const std::string file = s.file.string();
  auto fail = [&](const std::string& key, const std::string& msg) {
    throw Error(file + ": key '" + key + "': " + msg);
  };
  if (s.waypoints.empty()) fail("trajectory", "needs at least one waypoint");
  const NetGeometry net(s.pen, s.net);
  const bool cylinder = s.pen.shape == NetShape::kCylinder;
  for (size_t i = 0; i < s.waypoints.size(); ++i) {
    const Waypoint& w = s.waypoints[i];
    const std::string key = "trajectory.waypoints[" + std::to_string(i) + "]";
    if (!(w.net_distance_m > 0)) {
      fail(key + ".net_distance_m", "must be positive (the vehicle is inside the pen)");
    }
    if (cylinder && !(w.net_distance_m < s.pen.radius_m)) {
      fail(key + ".net_distance_m", "must be less than the pen radius");
    }
    if (!(w.depth_m > 0)) fail(key + ".depth_m", "must be below the surface (> 0)");
  }
  for (size_t i = 0; i < s.fish.size(); ++i) {
    if (cylinder && !(s.fish[i].net_distance_m < s.pen.radius_m)) {
      fail("fish[" + std::to_string(i) + "].net_distance_m", "must be less than the pen radius");
    }
  }
  // The net's u runs with a fold's length from along -circumference / 2 on (fold_arc_offset).
  const double half_around = std::numbers::pi * s.pen.radius_m;
  for (size_t i = 0; i < s.net.bulges.size(); ++i) {
    const Bulge& b = s.net.bulges[i];
    if (cylinder && b.fold && std::abs(b.along_m) + b.radius_m > half_around) {
      fail("net.bulges[" + std::to_string(i) + "].along_m",
           "a fold must end within along +-" + std::to_string(half_around) +
               " m (half the pen's circumference); move it by a circumference");
    }
  }
  // The camera, lamps and DVL ride on the vehicle; sample the whole run for the camera centre.
  const double step = 0.5 / s.camera.calibration.rate_hz;
  for (double t = 0; t <= s.duration_s + 1e-9; t += step) {
    const BodyState b = body_state(s, t);
    const Eigen::Vector3d c = b.T_pen_body * s.camera.calibration.T_body_camera.translation();
    if (net.clearance(c) <= 0) {
      fail("trajectory", "at t = " + at_time(t) + " the camera is outside the pen, " +
                             std::to_string(-net.clearance(c)) +
                             " m beyond the net; increase net_distance_m there");
    }
    if (c.z() <= 0) {
      fail("trajectory", "at t = " + at_time(t) + " the camera is above the water surface");
    }
    if (cylinder && c.z() >= s.pen.depth_m) {
      fail("trajectory", "at t = " + at_time(t) + " the camera is below the pen's depth_m");
    }
  }
}

}  // namespace pensight::sim
