// validate() of the global-pose configs and their parameter rows: a value out of range anywhere in
// a config gives the one message of core/params.h, with the key of the part that holds it; the
// constructors refuse it with the same message.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "tests/support/error_message.h"

namespace pensight::global_pose {
namespace {

using pensight::testing::error_message;

// The message validate() throws for `c`; empty when it passes.
std::string config_error(const GlobalPoseEstimatorConfig& c) {
  return error_message([&] { validate(c); });
}

TEST(GlobalPoseParams, DefaultsAndTheConfigsInUseAreValid) {
  EXPECT_EQ(config_error(GlobalPoseEstimatorConfig{}), "");
  EXPECT_EQ(error_message([] { validate(PublishedGlobalPoseConfig{}); }), "");
  // The lock rule turned off (global_pose_estimator_test.cpp), a flat panel 5 m out along x.
  GlobalPoseEstimatorConfig no_rule;
  no_rule.lock.min_inliers = 3;
  no_rule.lock.min_bearing_spread_rad = 0;
  no_rule.lock.max_r_sigma_m = 1e9;
  no_rule.lock.max_residual_rms_m = 1e9;
  no_rule.lock.reinit_after_rejected_fixes = 0;
  no_rule.pen_radius_m = 100;
  no_rule.flat_panel = SceneConfig::FlatPanel{.plane_point_m = Eigen::Vector3d(5, 0, 0)};
  EXPECT_EQ(config_error(no_rule), "");
}

TEST(GlobalPoseParams, ABadNestedValueNamesItsPrefixedKey) {
  GlobalPoseEstimatorConfig c;
  c.noise.process.yaw_accel = -1;
  const std::string e = config_error(c);
  EXPECT_EQ(e,
            "global pose: key 'noise.process.yaw_accel': -1 is outside >= 0 rad/s^2/sqrt(Hz) "
            "(yaw acceleration)");
  EXPECT_EQ(error_message([&] { GlobalPoseEstimator{c}; }), e);

  const testing::SpoiltConfig<GlobalPoseEstimatorConfig> bad[] = {
      {"key 'pen_radius_m': 0 is outside > 0 m (",
       [](GlobalPoseEstimatorConfig& x) { x.pen_radius_m = 0; }},
      {"key 'history_s': -1 is outside >= 0 s (",
       [](GlobalPoseEstimatorConfig& x) { x.history_s = -1; }},
      {"key 'relock_after_rejections': 0 is outside >= 1 (",
       [](GlobalPoseEstimatorConfig& x) { x.relock_after_rejections = 0; }},
      {"key 'circle.max_iterations': 0 is outside >= 1 (",
       [](GlobalPoseEstimatorConfig& x) { x.circle.max_iterations = 0; }},
      {"key 'noise.net_texture_max_unwrap_bars': 0.6 is outside (0, 0.5] bars (",
       [](GlobalPoseEstimatorConfig& x) { x.noise.net_texture_max_unwrap_bars = 0.6; }},
      {"key 'priors.psi_rate_window_s': none is outside > 0 s (",
       [](GlobalPoseEstimatorConfig& x) { x.priors.psi_rate_window_s = kNaN; }},
      {"key 'lock.agree_r_m': 0 is outside > 0 m (",
       [](GlobalPoseEstimatorConfig& x) { x.lock.agree_r_m = 0; }},
      {"key 'dvl_spikes.max_spike_samples': -1 is outside >= 0 (",
       [](GlobalPoseEstimatorConfig& x) { x.dvl_spikes.max_spike_samples = -1; }},
  };
  testing::expect_refused(
      bad, "global pose: ", [](const GlobalPoseEstimatorConfig& spoilt) { validate(spoilt); });
}

TEST(GlobalPoseParams, AFlatPanelFacingTheOriginIsRefused) {
  GlobalPoseEstimatorConfig c;
  c.flat_panel = SceneConfig::FlatPanel{.plane_point_m = Eigen::Vector3d(5, 0, 0),
                                        .plane_normal = -Eigen::Vector3d::UnitX()};
  EXPECT_TRUE(config_error(c).starts_with(
      "global pose: key 'flat_panel.plane_normal': must be horizontal and point away from"))
      << config_error(c);
  c.flat_panel->plane_normal = Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(config_error(c).starts_with("global pose: key 'flat_panel.plane_normal': "))
      << config_error(c);
}

TEST(GlobalPoseParams, ThePublishedNodeNamesItsCircleKeys) {
  PublishedGlobalPoseConfig c;
  c.circle.huber_delta_m = 0;
  const std::string e = error_message([&] { validate(c); });
  EXPECT_TRUE(
      e.starts_with("global pose (published): key 'circle.huber_delta_m': 0 is outside > 0 m ("))
      << e;
  EXPECT_EQ(error_message([&] { PublishedGlobalPose{c}; }), e);
}

TEST(GlobalPoseParams, RowsListEveryPartUnderItsPrefix) {
  const std::string rows = global_pose_param_rows();
  for (const char* row :
       {"| `pen_radius_m` | 12 | m | > 0 |", "| `has_dvl` | true |  | true, false |",
        "| `noise.process.yaw_accel` | 0.5 | rad/s^2/sqrt(Hz) | >= 0 |",
        "| `priors.released_depth_m` | 1 | m | > 0 |", "| `lock.min_inliers` | 12 |  | >= 0 |",
        "| `dvl_spikes.max_accel_mps2` | 0.4 | m/s^2 | > 0 |",
        "| `circle.max_hypotheses` | 64 |  | >= 0 |"}) {
    EXPECT_NE(rows.find(row), std::string::npos) << row << "\n" << rows;
  }
  // Set by the estimator, not parameters.
  EXPECT_EQ(rows.find("circle.radius_m"), std::string::npos);
  EXPECT_EQ(rows.find("dvl_spikes.noise_mps"), std::string::npos);
  const std::string published = published_global_pose_param_rows();
  EXPECT_NE(published.find("| `max_dvl_gap_s` | 1 | s | >= 0 |"), std::string::npos) << published;
  EXPECT_NE(published.find("| `circle.min_inliers` | 3 |"), std::string::npos) << published;
}

}  // namespace
}  // namespace pensight::global_pose
