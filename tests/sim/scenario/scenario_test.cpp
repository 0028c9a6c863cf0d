// Scenario parsing: the shipped scenarios load, and bad ones are refused with the key and file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "runtime/error.h"
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
  for (const char* name : {"sweep", "follow", "lawnmower", "lowlight", "turbid", "tank"}) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(source_dir() + "/scenarios/" + name + ".yaml");
    EXPECT_EQ(s.name, name);
    EXPECT_GE(s.num_frames(), 10);
    EXPECT_EQ(s.camera.calibration.camera.width_px, 720);
  }
}

TEST(Scenario, MinimalScenarioGetsDefaults) {
  const Scenario s = parse_scenario(kMinimal, "min.yaml");
  EXPECT_EQ(s.num_frames(), 21);
  EXPECT_DOUBLE_EQ(s.camera.calibration.camera.fx_px, 462.0);
  EXPECT_EQ(s.light.lamps.size(), 2u);
  const BodyState b = body_state(s, 1.0);
  EXPECT_NEAR(b.T_world_body.translation().x(), 12 - 1.25, 1e-12);
  EXPECT_NEAR(b.velocity_world_mps.x(), -0.25, 1e-9);
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
