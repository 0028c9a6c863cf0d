#pragma once
// Small scenes for the simulator tests: a one-pose scenario in a cylinder pen or a tank, at a
// reduced image size unless a test needs the real one.
#include <cstdio>
#include <string>

#include "sim/scenario.h"

namespace pensight::sim::testing {

struct Pose {
  double net_distance_m = 1.3;  // body origin; the camera sits 0.3 m ahead of it
  double heading_rad = 0, pitch_rad = 0, along_m = 0, depth_m = 4;
};

// `extra` is appended at the top level of the YAML (e.g. "fish: [...]\n").
inline Scenario one_pose(const Pose& p, int width = 180, int height = 135,
                         const std::string& pen = "{shape: cylinder, radius_m: 12, depth_m: 15}",
                         const std::string& extra = "", const std::string& camera_extra = "") {
  char buf[4096];
  std::snprintf(buf, sizeof buf,
                "seed: 5\n"
                "pen: %s\n"
                "net: {fouling: 0.3, bulges: []}\n"
                "camera: {resolution: [%d, %d], samples_per_axis: 2%s}\n"
                "trajectory:\n"
                "  waypoints:\n"
                "    - {t_s: 0, along_m: %.9g, net_distance_m: %.9g, depth_m: %.9g, "
                "heading_rad: %.9g, pitch_rad: %.9g}\n"
                "%s",
                pen.c_str(), width, height, camera_extra.c_str(), p.along_m, p.net_distance_m,
                p.depth_m, p.heading_rad, p.pitch_rad, extra.c_str());
  return parse_scenario(buf, "test.yaml");
}

}  // namespace pensight::sim::testing
