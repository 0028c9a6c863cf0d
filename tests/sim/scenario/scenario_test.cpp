// Scenario parsing: the shipped scenarios load, and bad ones are refused with the key and file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/sensor_mounts.h"
#include "sim/scenario.h"
#include "sim/trajectory.h"
#include "tests/sim/sim_test_scenes.h"

namespace pensight::sim {
namespace {

std::string source_dir() {
  const char* d = std::getenv("PENSIGHT_SOURCE_DIR");
  return d ? d : ".";
}

std::string error_of(const std::string& yaml) {
  try {
    parse_scenario(yaml, "bad.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

const char* kMinimal =
    "trajectory:\n  waypoints:\n    - {t_s: 0, net_distance_m: 1.0, depth_m: 3}\n"
    "    - {t_s: 2, net_distance_m: 1.5, depth_m: 3}\n";

TEST(Scenario, ShippedScenariosLoad) {
  for (const char* name :
       {"sweep", "follow", "lawnmower", "lowlight", "turbid", "tank", "follow_drift", "diamond"}) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(source_dir() + "/scenarios/" + name + ".yaml");
    EXPECT_EQ(s.name, name);
    EXPECT_GE(s.num_frames(), 10);
    EXPECT_EQ(s.camera.calibration.camera.width_px, 720);
  }
  // The real SOLAQUA camera's size.
  const Scenario s = load_scenario(source_dir() + "/scenarios/solaqua.yaml");
  EXPECT_EQ(s.camera.calibration.camera.width_px, 1280);
  EXPECT_EQ(s.num_frames(), 101);
  EXPECT_EQ(s.net.mesh_type, MeshType::kSquare);
  EXPECT_DOUBLE_EQ(s.net.opening_angle_deg, 100);
}

TEST(Scenario, NetMeshKeysParse) {
  const Scenario d = parse_scenario(kMinimal, "min.yaml");
  EXPECT_EQ(d.net.mesh_type, MeshType::kSquare);
  EXPECT_EQ(d.net.opening_angle_deg, 90);
  EXPECT_EQ(d.net.opening_angle_variation_deg, 0);
  EXPECT_EQ(d.net.stretch_variation, 0);
  EXPECT_EQ(d.net.deform_scale_m, 3);
  EXPECT_EQ(d.net.knot_shape, KnotShape::kSquare);
  EXPECT_EQ(d.net.fouling_coverage, 0);
  EXPECT_EQ(d.net.ropes.spacing_m, 0);
  EXPECT_EQ(d.net.ropes.width_m, 0.02);
  EXPECT_EQ(d.net.ropes.albedo, 0.6);
  EXPECT_EQ(d.net.seam_spacing_m, 0);
  const Scenario s = parse_scenario(
      std::string(kMinimal) +
          "net: {mesh_m: 0.03, mesh_type: diamond, opening_angle_deg: 75, "
          "opening_angle_variation_deg: 3, stretch_variation: 0.03, deform_scale_m: 2.5, "
          "twine_width_m: 0.009, knot_size_m: 0.012, knot_shape: round, fouling_coverage: 0.5, "
          "ropes: {spacing_m: 1.5, width_m: 0.025, albedo: 0.5}, seam_spacing_m: 4}\n",
      "ok.yaml");
  EXPECT_EQ(s.net.mesh_type, MeshType::kDiamond);
  EXPECT_EQ(s.net.opening_angle_deg, 75);
  EXPECT_EQ(s.net.opening_angle_variation_deg, 3);
  EXPECT_EQ(s.net.stretch_variation, 0.03);
  EXPECT_EQ(s.net.deform_scale_m, 2.5);
  EXPECT_EQ(s.net.twine_width_m, 0.009);  // 30 % of the bar
  EXPECT_EQ(s.net.knot_size_m, 0.012);
  EXPECT_EQ(s.net.knot_shape, KnotShape::kRound);
  EXPECT_EQ(s.net.fouling_coverage, 0.5);
  EXPECT_EQ(s.net.ropes.spacing_m, 1.5);
  EXPECT_EQ(s.net.ropes.width_m, 0.025);
  EXPECT_EQ(s.net.ropes.albedo, 0.5);
  EXPECT_EQ(s.net.seam_spacing_m, 4);
  // scene.yaml gets the mesh type and the nominal opening angle.
  const SceneConfig scene = s.scene_config();
  EXPECT_EQ(scene.net_mesh_type, MeshType::kDiamond);
  ASSERT_TRUE(scene.net_mesh_angle_rad);
  EXPECT_NEAR(*scene.net_mesh_angle_rad, deg_to_rad(75), 1e-15);
}

TEST(Scenario, BadNetMeshValuesAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      {"mesh_type: hexagonal", "'net.mesh_type': must be 'square' or 'diamond', got 'hexagonal'"},
      {"opening_angle_deg: 30", "'net.opening_angle_deg': must be between 45"},
      {"opening_angle_deg: 140", "'net.opening_angle_deg': must be between 45"},
      {"opening_angle_variation_deg: 12", "'net.opening_angle_variation_deg': must be between"},
      {"stretch_variation: 0.1", "'net.stretch_variation': must be between 0"},
      {"deform_scale_m: 0.1", "'net.deform_scale_m': must be between"},
      {"twine_width_m: 0.011", "'net.twine_width_m': must be less than 0.35 * mesh_m"},
      {"knot_size_m: 0.019", "'net.knot_size_m': must be less than 0.6 * mesh_m"},
      {"knot_shape: star", "'net.knot_shape': must be 'square' or 'round', got 'star'"},
      {"fouling_coverage: 0.8", "'net.fouling_coverage': must be between 0"},
      {"ropes: {spacing_m: 0.05}", "'net.ropes.spacing_m': must be 0 (no ropes) or at least"},
      {"ropes: {width_m: 0.5}", "'net.ropes.width_m': must be between"},
      {"ropes: {albedo: 2}", "'net.ropes.albedo': must be between 0"},
      {"ropes: {spacing: 1}", "'net.ropes.spacing': unknown key"},
      {"seam_spacing_m: 0.04", "'net.seam_spacing_m': must be 0 (no seams) or at least"},
      {"mesh_angle_rad: 0.7", "'net.mesh_angle_rad': unknown key"},
  };
  for (const auto& [yaml, message] : cases) {
    const std::string e = error_of(std::string(kMinimal) + "net: {mesh_m: 0.03, " + yaml + "}\n");
    EXPECT_NE(e.find(message), std::string::npos) << yaml << ": " << e;
  }
}

TEST(Scenario, MinimalScenarioGetsDefaults) {
  const Scenario s = parse_scenario(kMinimal, "min.yaml");
  EXPECT_EQ(s.num_frames(), 21);
  EXPECT_DOUBLE_EQ(s.camera.calibration.camera.fx_px, 462.0);
  EXPECT_EQ(s.light.lamps.size(), 2u);
  const BodyState b = body_state(s, 1.0);
  EXPECT_NEAR(b.T_pen_body.translation().x(), 12 - 1.25, 1e-12);
  EXPECT_NEAR(b.velocity_pen_mps.x(), -0.25, 1e-9);
}

// The sweep reverses distance and heading at its waypoints: the body velocity must change
// smoothly through them (a linear interpolation jumps by up to 2.6 m/s), the camera must not
// overshoot the waypoints' distance range, and a constant-rate segment stays linear (above).
TEST(Scenario, TrajectoryVelocityIsContinuousWithoutOvershoot) {
  const Scenario s = load_scenario(source_dir() + "/scenarios/sweep.yaml");
  double lo = 1e9, hi = -1e9;
  for (const Waypoint& w : s.waypoints) {
    lo = std::min(lo, w.net_distance_m);
    hi = std::max(hi, w.net_distance_m);
  }
  const double t0 = s.waypoints.front().t_s;
  for (size_t k = 1; k + 1 < s.waypoints.size(); ++k) {
    SCOPED_TRACE("waypoint " + std::to_string(k));
    const double t = s.waypoints[k].t_s - t0;
    const Eigen::Vector3d before = body_state(s, t - 1e-3).velocity_pen_mps;
    const Eigen::Vector3d after = body_state(s, t + 1e-3).velocity_pen_mps;
    EXPECT_LT((after - before).norm(), 0.02);
  }
  for (double t = 0; t <= s.waypoints.back().t_s - t0; t += 0.01) {
    const Eigen::Vector3d p = body_state(s, t).T_pen_body.translation();
    const double net_distance_m = s.pen.radius_m - std::hypot(p.x(), p.y());
    EXPECT_GE(net_distance_m, lo - 1e-9);
    EXPECT_LE(net_distance_m, hi + 1e-9);
  }
}

TEST(Scenario, StartTimeKeepsEveryNanosecond) {
  const Scenario s =
      parse_scenario(std::string(kMinimal) + "start_time_ns: 1600000000123456789\n", "t.yaml");
  EXPECT_EQ(s.frame_time_ns(1), 1600000000223456789);
  EXPECT_NE(error_of(std::string(kMinimal) + "start_time_ns: 1.5\n").find("whole number"),
            std::string::npos);
}

TEST(Scenario, TypoIsNamedWithItsFile) {
  const std::string e = error_of(std::string(kMinimal) + "water: {attenuation_per_n: 0.3}\n");
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("water.attenuation_per_n"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
  // Scenarios are the project's own input, so unlike dataset files they stay strict at every level.
  const std::string top = error_of(std::string(kMinimal) + "pen_radius_m: 12\n");
  EXPECT_NE(top.find("bad.yaml: key 'pen_radius_m': unknown key"), std::string::npos) << top;
}

TEST(Scenario, ImpossibleValuesAreRefused) {
  std::string e = error_of(std::string(kMinimal) + "pen: {radius_m: -3}\n");
  EXPECT_NE(e.find("pen.radius_m"), std::string::npos) << e;
  EXPECT_NE(e.find("positive"), std::string::npos) << e;
  // Body 0.2 m from the net with the camera 0.3 m ahead of it: the camera is outside the pen.
  e = error_of(
      "trajectory:\n  waypoints:\n    - {t_s: 0, net_distance_m: 1.0, depth_m: 3}\n"
      "    - {t_s: 2, net_distance_m: 0.2, depth_m: 3}\n");
  EXPECT_NE(e.find("outside the pen"), std::string::npos) << e;
  e = error_of("trajectory:\n  waypoints:\n    - {t_s: 0, net_distance_m: 1.0, depth_m: -1}\n");
  EXPECT_NE(e.find("depth_m"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "net: {mesh_m: 0.03, twine_width_m: 0.02}\n");
  EXPECT_NE(e.find("net.twine_width_m"), std::string::npos) << e;
  e = error_of("seed: 3\n");
  EXPECT_NE(e.find("'trajectory': missing"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "pen: {shape: sphere}\n");
  EXPECT_NE(e.find("'cylinder' or 'plane'"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "water: {current_mps: [5, 0, 0]}\n");
  EXPECT_NE(e.find("water.current_mps"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "water: {current_mps: [0.1, 0]}\n");
  EXPECT_NE(e.find("water.current_mps"), std::string::npos) << e;
  // Sizes that would make the loaders loop or allocate without bound.
  e = error_of(std::string(kMinimal) + "duration_s: 1e9\n");
  EXPECT_NE(e.find("'duration_s': must be between 0 and 21600 s"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "camera: {rate_hz: 1e9}\n");
  EXPECT_NE(e.find("camera.rate_hz"), std::string::npos) << e;
  e = error_of(
      "trajectory:\n  lawnmower: {net_distances_m: [1.0], depth_from_m: 2, depth_to_m: 1e9}\n");
  EXPECT_NE(e.find("more than 1000 rows"), std::string::npos) << e;
}

TEST(Scenario, DvlErrorsAndSpikesParse) {
  const Scenario s = parse_scenario(
      std::string(kMinimal) +
          "dvl: {scale_error: 0.01, bias_mps: [0.004, 0.003, 0], spikes: [{t_s: 2, duration_s: "
          "0.5, velocity_mps: [0, 2, 0]}]}\n",
      "ok.yaml");
  EXPECT_DOUBLE_EQ(s.dvl.scale_error, 0.01);
  EXPECT_DOUBLE_EQ(s.dvl.bias_B_mps.y(), 0.003);
  ASSERT_EQ(s.dvl.spikes.size(), 1u);
  EXPECT_DOUBLE_EQ(s.dvl.spikes[0].t_s, 2.0);
  EXPECT_DOUBLE_EQ(s.dvl.spikes[0].velocity_B_mps.y(), 2.0);
  std::string e = error_of(std::string(kMinimal) + "dvl: {spikes: [{t_s: 2, duration_s: -1}]}\n");
  EXPECT_NE(e.find("duration_s"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "dvl: {spikes: [{t_s: 2, speed: 1}]}\n");
  EXPECT_NE(e.find("speed"), std::string::npos) << e;
  e = error_of(std::string(kMinimal) + "dvl: {scale_error: 2}\n");
  EXPECT_NE(e.find("dvl.scale_error"), std::string::npos) << e;
}

TEST(Scenario, MissingFileIsNamed) {
  try {
    load_scenario("/nonexistent/where.yaml");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/where.yaml"), std::string::npos);
  }
}

TEST(Scenario, CameraMountLooksForward) {
  const Eigen::Isometry3d T = forward_mount({0.3, 0, 0}, 0, 0);
  EXPECT_TRUE(T.linear().col(2).isApprox(Eigen::Vector3d::UnitX()));  // optical axis = forward
  const Eigen::Isometry3d down = forward_mount({0, 0, 0}, 0, 0.3);
  EXPECT_GT(down.linear().col(2).z(), 0.29);  // tilt > 0 looks down (+z body)
}

}  // namespace
}  // namespace pensight::sim
