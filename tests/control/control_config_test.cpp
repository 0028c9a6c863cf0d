#include "control/control_config.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/strict_yaml.h"

namespace pensight::control {
namespace {

ControlConfig parse(const std::string& yaml) {
  return parse_control_config(YamlMap::parse(yaml, "control.yaml"));
}

std::string error_of(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ControlConfig, DefaultsAreThePublishedGains) {
  const ControlConfig c = parse("strategy: dvl\n");
  EXPECT_EQ(c.gains.surge_position.kp, 3.0);
  EXPECT_EQ(c.gains.surge_position.kd, 0.3);
  EXPECT_EQ(c.gains.sway_position.kp, 30.0);
  EXPECT_EQ(c.gains.sway_position.ki, 0.001);
  EXPECT_EQ(c.gains.yaw.kp, 0.075);
  EXPECT_EQ(c.gains.yaw.ki, 0.007);
  EXPECT_EQ(c.gains.yaw.kd, 0.008);
  EXPECT_EQ(c.gains.surge_velocity.kp, 10.0);
  EXPECT_EQ(c.gains.surge_velocity.ki, 1.0);
  ASSERT_EQ(c.legs.size(), 1u);
}

TEST(ControlConfig, ReadsLegsGainsAndStrategy) {
  const ControlConfig c = parse(R"(
strategy: open_loop
legs:
  - {d_ref_m: 0.5, sway_speed_mps: 0.1, length_m: 3}
  - {d_ref_m: 1.0, sway_speed_mps: -0.1, duration_s: 20, depth_m: 4}
gains:
  yaw: {kp: 0.1}
safety: {backoff_after_s: 4}
)");
  EXPECT_EQ(c.strategy, VelocityStrategy::kOpenLoop);
  ASSERT_EQ(c.legs.size(), 2u);
  EXPECT_EQ(c.legs[0].length_m, 3);
  EXPECT_TRUE(std::isinf(c.legs[0].duration_s));
  EXPECT_TRUE(std::isnan(c.legs[0].depth_m));
  EXPECT_EQ(c.legs[1].depth_m, 4);
  EXPECT_EQ(c.gains.yaw.kp, 0.1);
  EXPECT_EQ(c.gains.yaw.kd, 0.008);  // the rest keeps its default
  EXPECT_EQ(c.safety.backoff_after_s, 4);
}

TEST(ControlConfig, BadInputNamesTheKey) {
  EXPECT_NE(error_of("gains: {yaw: {kpp: 1}}").find("'gains.yaw.kpp'"), std::string::npos);
  EXPECT_NE(error_of("gains: {yaw: {kp: -1}}").find("'gains.yaw.kp'"), std::string::npos);
  EXPECT_NE(error_of("gains: {yaw: {kd: .nan}}").find("gains.yaw.kd"), std::string::npos);
  EXPECT_NE(error_of("gains: {surge_position: {kp: 0}}").find("uncontrolled"), std::string::npos);
  EXPECT_NE(error_of("strategy: pwm").find("dvl or open_loop"), std::string::npos);
  EXPECT_NE(error_of("legs: []").find("'legs'"), std::string::npos);
  EXPECT_NE(error_of("legs: [{d_ref_m: 0}]").find("legs[0].d_ref_m"), std::string::npos);
  EXPECT_NE(error_of("legs: [{d_ref_m: 1, sway_speed_mps: 2}]").find("limits.sway_speed_mps"),
            std::string::npos);
  EXPECT_NE(error_of("safety: {backoff_after_s: 0.1}").find("safety.backoff_after_s"),
            std::string::npos);
  EXPECT_NE(error_of("vehicle: {pilot_gain: 0}").find("vehicle.pilot_gain"), std::string::npos);
  EXPECT_NE(error_of("speed: 1").find("'speed'"), std::string::npos);
  EXPECT_NE(error_of("- 1").find("control.yaml"), std::string::npos);
}

}  // namespace
}  // namespace pensight::control
