// validate() of the dense-depth configs and the stage's parameter rows: a value out of range gives
// the one message of core/params.h, with the key as the rows name it; the constructors refuse it
// with the same message.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/dvl_depth_scale.h"
#include "pipeline/depth/dvl_net_tilt.h"
#include "sim/sensors.h"
#include "tests/support/error_message.h"
#include "tests/support/flat_net_world.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::camera_mount;
using testing::error_message;

TEST(DepthParams, DefaultsAreValid) {
  EXPECT_EQ(error_message([] { validate(DepthEstimatorConfig{}); }), "");
  EXPECT_EQ(error_message([] { validate(DvlDepthScaleConfig{}); }), "");
  EXPECT_EQ(error_message([] { validate(DvlNetTiltConfig{}); }), "");
  // The values in use: the DVL tests' min_samples = 1, a cylinder's curvature.
  EXPECT_EQ(error_message([] { validate(DvlDepthScaleConfig{.min_samples = 1}); }), "");
  EXPECT_EQ(error_message([] { validate(DvlNetTiltConfig{.min_samples = 1}); }), "");
  EXPECT_EQ(error_message([] { validate(DepthEstimatorConfig{.net_curvature_per_m = 1 / 12.0}); }),
            "");
}

TEST(DepthParams, ABadNestedValueNamesItsPrefixedKey) {
  DepthEstimatorConfig depth{.model = "missing.onnx"};
  depth.plane.iterations = 0;
  const std::string e = error_message([&] { validate(depth); });
  EXPECT_EQ(e,
            "depth: key 'plane.iterations': 0 is outside >= 1 (reweighted least-squares "
            "iterations)");
  // The constructor refuses it with the same message, before it reads the model.
  EXPECT_EQ(error_message([&] { DepthEstimator(PinholeCamera{}, depth, testing::test_device()); }),
            e);

  DepthEstimatorConfig sigma;
  sigma.sigma_px = 0;
  EXPECT_TRUE(error_message([&] { validate(sigma); })
                  .starts_with("depth: key 'sigma_px': 0 is outside "
                               "> 0 px ("));
  DepthEstimatorConfig share;
  share.plane.central_share = kNaN;
  EXPECT_TRUE(error_message([&] {
                validate(share);
              }).starts_with("depth: key 'plane.central_share': none is outside (0, 1] ("));
}

TEST(DepthParams, TheDvlCorrectionsNameTheirKeys) {
  const DvlCalibration dvl = sim::dvl_calibration(sim::DvlConfig{});
  DvlDepthScaleConfig scale;
  scale.window_s = 0;
  EXPECT_EQ(
      error_message([&] { DvlDepthScale(PinholeCamera{}, camera_mount(), dvl, scale); }),
      "depth: key 'dvl_depth_scale.window_s': 0 is outside > 0 s (the median's window; the net's "
      "stretch varies over metres)");
  DvlNetTiltConfig tilt;
  tilt.range_noise_m = kNaN;
  EXPECT_EQ(error_message([&] { DvlNetTilt(camera_mount(), dvl, tilt); }),
            "depth: key 'dvl_net_tilt.range_noise_m': none is outside >= 0 m (the DVL's range "
            "noise, 1 sigma: the floor of the window's standard error)");
}

TEST(DepthParams, RowsListEveryPartUnderItsPrefix) {
  const std::string rows = depth_param_rows();
  for (const char* row : {"| `sigma_px` | 10 | px | > 0 |", "| `plane.iterations` | 4 |  | >= 1 |",
                          "| `dvl_depth_scale.window_s` | 10 | s | > 0 |",
                          "| `dvl_net_tilt.trusted_rad` | 0.01745 | rad | >= 0 |"}) {
    EXPECT_NE(rows.find(row), std::string::npos) << row << "\n" << rows;
  }
}

}  // namespace
}  // namespace pensight
