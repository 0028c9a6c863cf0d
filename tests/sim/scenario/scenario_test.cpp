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
  for (const char* name : {"sweep", "follow", "lawnmower", "lowlight", "turbid", "tank",
                           "follow_drift", "diamond", "changing_net", "fold"}) {
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
      {"opening_angle_deg: 30", "'net.opening_angle_deg': 30 is outside 45 to 135 deg"},
      {"opening_angle_deg: 140", "'net.opening_angle_deg': 140 is outside 45 to 135 deg"},
      {"opening_angle_variation_deg: 12",
       "'net.opening_angle_variation_deg': 12 is outside 0 to 10 deg"},
      {"stretch_variation: 0.1", "'net.stretch_variation': 0.1 is outside 0 to 0.05 ("},
      {"deform_scale_m: 0.1", "'net.deform_scale_m': 0.1 is outside 0.2 to 100 m"},
      {"twine_width_m: 0.011", "'net.twine_width_m': must be less than 0.35 * mesh_m"},
      {"knot_size_m: 0.019", "'net.knot_size_m': must be less than 0.6 * mesh_m"},
      {"knot_shape: star", "'net.knot_shape': must be 'square' or 'round', got 'star'"},
      {"fouling_coverage: 0.8", "'net.fouling_coverage': 0.8 is outside 0 to 0.7 ("},
      {"ropes: {spacing_m: 0.05}", "'net.ropes.spacing_m': must be 0 (no ropes) or at least"},
      {"ropes: {width_m: 0.5}", "'net.ropes.width_m': 0.5 is outside 0.001 to 0.2 m"},
      {"ropes: {albedo: 2}", "'net.ropes.albedo': 2 is outside 0 to 1 ("},
      {"ropes: {spacing: 1}", "'net.ropes.spacing': unknown key"},
      {"seam_spacing_m: 0.04", "'net.seam_spacing_m': must be 0 (no seams) or at least"},
      {"mesh_angle_rad: 0.7", "'net.mesh_angle_rad': unknown key"},
  };
  for (const auto& [yaml, message] : cases) {
    const std::string e = error_of(std::string(kMinimal) + "net: {mesh_m: 0.03, " + yaml + "}\n");
    EXPECT_NE(e.find(message), std::string::npos) << yaml << ": " << e;
  }
}

// A changing net: each change starts from the net before it, the net in view follows the time,
// and what would make the scene's prior or the wall change is refused.
TEST(Scenario, NetChangesParse) {
  const Scenario s =
      parse_scenario(std::string(kMinimal) +
                         "net: {mesh_m: 0.03, twine_width_m: 0.004, knot_shape: round}\n"
                         "net_changes:\n"
                         "  - {t_s: 0.5, net: {mesh_type: diamond, opening_angle_deg: 75}}\n"
                         "  - {t_s: 1.2, net: {opening_angle_deg: 110, fouling: 0.6}}\n",
                     "ok.yaml");
  ASSERT_EQ(s.net_changes.size(), 2u);
  EXPECT_EQ(s.net_changes[0].net.mesh_type, MeshType::kDiamond);
  EXPECT_EQ(s.net_changes[0].net.twine_width_m, 0.004);  // kept from `net`
  EXPECT_EQ(s.net_changes[0].net.knot_shape, KnotShape::kRound);
  EXPECT_EQ(s.net_changes[1].net.mesh_type, MeshType::kDiamond);  // kept from the first change
  EXPECT_EQ(s.net_changes[1].net.opening_angle_deg, 110);
  EXPECT_EQ(s.net_changes[1].net.bar_length_m, 0.03);
  EXPECT_EQ(s.net_index_at(0.0), 0u);
  EXPECT_EQ(s.net_index_at(0.4999), 0u);
  EXPECT_EQ(s.net_index_at(0.5), 1u);
  EXPECT_EQ(s.net_index_at(2.0), 2u);
  EXPECT_EQ(s.net_at(0.7).opening_angle_deg, 75);
  const Scenario one = s.with_net_at(1.5);
  EXPECT_TRUE(one.net_changes.empty());
  EXPECT_EQ(one.net.opening_angle_deg, 110);
  // The scene's prior (scene.yaml) is the first net's.
  EXPECT_EQ(s.scene_config().net_mesh_type, MeshType::kSquare);
  // A change on a frame's time lands on that frame.
  const Scenario sweep = load_scenario(source_dir() + "/scenarios/changing_net.yaml");
  EXPECT_EQ(sweep.net_index_at(8 / sweep.camera.calibration.rate_hz), 1u);
  EXPECT_EQ(sweep.net_index_at(7 / sweep.camera.calibration.rate_hz), 0u);
}

TEST(Scenario, BadNetChangesAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      {"  - {net: {opening_angle_deg: 80}}\n", "'net_changes[0].t_s': missing"},
      {"  - {t_s: 0, net: {opening_angle_deg: 80}}\n", "'net_changes[0].t_s': must be after"},
      {"  - {t_s: 1, net: {opening_angle_deg: 80}}\n  - {t_s: 0.5, net: {fouling: 0.1}}\n",
       "'net_changes[1].t_s': must increase"},
      {"  - {t_s: 3, net: {opening_angle_deg: 80}}\n", "'net_changes': the last change"},
      {"  - {t_s: 1, net: {mesh_m: 0.02}}\n", "'net_changes[0].net.mesh_m': stays the first"},
      {"  - {t_s: 1, net: {opening_angle_deg: 150}}\n",
       "'net_changes[0].net.opening_angle_deg': 150 is outside 45 to 135 deg"},
      {"  - {t_s: 1, net: {fouling: 0.1}, angle: 3}\n", "'net_changes[0].angle': unknown key"},
  };
  for (const auto& [yaml, message] : cases) {
    const std::string e = error_of(std::string(kMinimal) + "net_changes:\n" + yaml);
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
  // Every key of the section is named as known, the absent ones too.
  EXPECT_NE(e.find("known keys here: attenuation_per_m, backscatter, current_mps, "
                   "diffuse_attenuation_per_m, lamp_backscatter, marine_snow, snow_brightness"),
            std::string::npos)
      << e;
  const std::string top = error_of(std::string(kMinimal) + "pen_radius_m: 12\n");
  EXPECT_NE(top.find("bad.yaml: key 'pen_radius_m': unknown key"), std::string::npos) << top;
}

TEST(Scenario, ImpossibleValuesAreRefused) {
  std::string e = error_of(std::string(kMinimal) + "pen: {radius_m: -3}\n");
  EXPECT_NE(e.find("'pen.radius_m': -3 is outside > 0 m ("), std::string::npos) << e;
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
  EXPECT_NE(e.find("'duration_s': 1e+09 is outside 0 to 21600 s"), std::string::npos) << e;
  // Without duration_s the waypoints' span is held to the same range.
  e = error_of(
      "trajectory:\n  waypoints:\n    - {t_s: 0, net_distance_m: 1.0, depth_m: 3}\n"
      "    - {t_s: 30000, net_distance_m: 1.5, depth_m: 3}\n");
  EXPECT_NE(e.find("bad.yaml: key 'duration_s': 30000 is outside 0 to 21600 s"), std::string::npos)
      << e;
  e = error_of(std::string(kMinimal) + "camera: {rate_hz: 1e9}\n");
  EXPECT_NE(e.find("camera.rate_hz"), std::string::npos) << e;
  e = error_of(
      "trajectory:\n  lawnmower: {net_distances_m: [1.0], depth_from_m: 2, depth_to_m: 1e9}\n");
  EXPECT_NE(e.find("more than 1000 rows"), std::string::npos) << e;
}

// Every number out of its range gets the one message of core/params.h: file, key path, value,
// range, unit and what the key means.
TEST(Scenario, OutOfRangeValueGetsTheUniformMessage) {
  EXPECT_EQ(error_of(std::string(kMinimal) + "net: {albedo: 1.5}\n"),
            "bad.yaml: key 'net.albedo': 1.5 is outside 0 to 1 (twine albedo)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "light: {lamps: [{intensity: -1}]}\n"),
            "bad.yaml: key 'light.lamps[0].intensity': -1 is outside 0 to 1000 (irradiance at 1 m "
            "on the axis, in clear water)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "camera: {samples_per_axis: 9}\n"),
            "bad.yaml: key 'camera.samples_per_axis': 9 is outside 1 to 8 (supersampling: N x N "
            "rays per pixel)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "vehicle: {pilot_gain: 2}\n"),
            "bad.yaml: key 'vehicle.pilot_gain': 2 is outside (0, 1] (ArduSub's joystick gain)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "seed: -1\n"),
            "bad.yaml: key 'seed': -1 is outside 0 to 9e+15 (random seed of the noise, net "
            "deformation and current; a whole number)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "seed: 1.5\n"),
            "bad.yaml: key 'seed': must be a whole number");
}

TEST(Scenario, MissingRequiredKeyIsRefused) {
  EXPECT_EQ(error_of("trajectory:\n  waypoints:\n    - {t_s: 0, net_distance_m: 1.0}\n"),
            "bad.yaml: key 'trajectory.waypoints[0].depth_m': missing; add it (body origin's "
            "depth)");
  EXPECT_EQ(error_of(std::string(kMinimal) + "net: {bulges: [{depth_m: 4}]}\n"),
            "bad.yaml: key 'net.bulges[0].along_m': missing; add it (centre's arc length along "
            "the net)");
  EXPECT_EQ(
      error_of("trajectory:\n  lawnmower: {net_distances_m: [1.0], depth_from_m: 2}\n"),
      "bad.yaml: key 'trajectory.lawnmower.depth_to_m': missing; add it (rows down to this depth, "
      "not above depth_from_m)");
}

// A fold is read with its flag; one steeper than the intersection converges for is refused.
TEST(Scenario, FoldsParseAndASteepFoldIsRefused) {
  const Scenario s = parse_scenario(std::string(kMinimal) +
                                        "net: {bulges: [{along_m: 1, depth_m: 4, amplitude_m: "
                                        "0.3, radius_m: 1.5, fold: true}]}\n",
                                    "fold.yaml");
  ASSERT_EQ(s.net.bulges.size(), 1u);
  EXPECT_TRUE(s.net.bulges[0].fold);
  EXPECT_EQ(s.net.bulges[0].amplitude_m, 0.3);
  EXPECT_EQ(error_of(std::string(kMinimal) + "net: {bulges: [{along_m: 1, depth_m: 4, "
                                             "amplitude_m: -0.8, radius_m: 1.5, fold: true}]}\n"),
            "bad.yaml: key 'net.bulges[0].amplitude_m': a fold's slope amplitude_m / radius_m "
            "must be at most 0.5");
}

// A fold that crosses along +-half the circumference (where u wraps) is refused by name.
TEST(Scenario, AFoldAcrossTheWrapIsRefused) {
  EXPECT_EQ(error_of(std::string(kMinimal) + "net: {bulges: [{along_m: 37, depth_m: 4, "
                                             "amplitude_m: 0.3, radius_m: 1.5, fold: true}]}\n"),
            "bad.yaml: key 'net.bulges[0].along_m': a fold must end within along +-37.699112 m "
            "(half the pen's circumference); move it by a circumference");
}

// A key written without a value keeps its default, as before the keys were read from tables.
TEST(Scenario, KeyWithoutValueKeepsItsDefault) {
  const Scenario s = parse_scenario(std::string(kMinimal) + "pen: {radius_m: }\nseed:\n", "n.yaml");
  EXPECT_EQ(s.pen.radius_m, 12.0);
  EXPECT_EQ(s.seed, 1u);
}

TEST(Scenario, ParamRowsNameEveryKeyWithItsSection) {
  const std::string rows = scenario_param_rows();
  for (const char* row :
       {"| `seed` | 1 |  | 0 to 9e+15 |", "| `duration_s` | none | s | 0 to 21600 |",
        "| `camera.rate_hz` | 10 | Hz | 0.1 to 1000 | frame rate |",
        "| `net.mesh_m` | 0.03 | m | > 0 | bar length, knot to knot |",
        "| `net.ropes.width_m` | 0.02 | m | 0.001 to 0.2 | rope width |",
        "| `net.bulges[].along_m` | required | m | any |",
        "| `water.attenuation_per_m` | 0.25 | 1/m | 0.01 to 20 |",
        "| `light.lamps[].intensity` | 0.06 |  | 0 to 1000 |",
        "| `dvl.enabled` | true |  | true, false |",
        "| `dvl.spikes[].duration_s` | 0.5 | s | > 0 |",
        "| `trajectory.waypoints[].t_s` | required | s | any |",
        "| `trajectory.lawnmower.row_spacing_m` | 0.5 | m | > 0 |",
        "| `net_changes[].t_s` | required | s | 0 to 21600 |",
        "| `vehicle.pilot_gain` | 0.5 |  | (0, 1] |"}) {
    EXPECT_NE(rows.find(row), std::string::npos) << row << " not in\n" << rows;
  }
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 101);
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
