// Accuracy of the whole FFT stage (CPU path) on rendered planar nets against their known truth.
#include <gtest/gtest.h>

#include "tests/pipeline/fft_detection/sweep.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::NetScene;

std::vector<ImageU8> render_all(const PinholeCamera& cam, const std::vector<NetScene>& scenes) {
  std::vector<ImageU8> frames;
  for (const NetScene& s : scenes) frames.push_back(testing::render_net(cam, s));
  return frames;
}

TEST(FftAccuracy, SweepMeetsBounds) {
  const PinholeCamera cam{.k1 = -0.04, .k2 = 0.01};
  const auto scenes = testing::sweep_scenes(24, testing::fresh_seed(), {.supersample = 2});
  const auto frames = render_all(cam, scenes);
  NetDetector detector(cam, {.backend = Backend::kCpu});
  const auto e = testing::run_sweep(cam, frames, scenes, detector, true);
  testing::print_errors("default", e);
  EXPECT_EQ(e.invalid, 0);
  EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.02);
  EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 1.0);
}

// Turbid water (contrast halves every ~0.7 m) and low light (dark, noisy, low contrast).
TEST(FftAccuracy, TurbidAndLowLight) {
  const PinholeCamera cam;
  const uint64_t seed = testing::fresh_seed();
  const NetScene turbid{.net_level = 150,
                        .water_level = 90,
                        .attenuation_m = 1.0,
                        .noise_sigma = 4,
                        .supersample = 2};
  const NetScene low_light{.net_level = 40, .water_level = 15, .noise_sigma = 6, .supersample = 2};
  for (const auto& [label, base] :
       {std::pair{"turbid", turbid}, std::pair{"low light", low_light}}) {
    const auto scenes = testing::sweep_scenes(12, seed, base);
    NetDetector detector(cam, {.backend = Backend::kCpu});
    const auto e = testing::run_sweep(cam, render_all(cam, scenes), scenes, detector, true);
    testing::print_errors(label, e);
    EXPECT_LE(e.invalid, 1) << label;
    EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.02) << label;
    EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 1.0) << label;
  }
}

// Frames without a net must give NaN and a reason, never a number.
TEST(FftAccuracy, NoNetGivesNanWithReason) {
  const PinholeCamera cam;
  std::mt19937_64 rng(testing::fresh_seed());
  NetDetector detector(cam, {.backend = Backend::kCpu});
  for (int i = 0; i < 4; ++i) {
    const auto d = detector.detect(testing::render_noise(720, 540, 0, 255, rng()));
    EXPECT_FALSE(d.pose.valid());
    EXPECT_TRUE(std::isnan(d.pose.d_net_m));
    EXPECT_TRUE(std::isnan(d.pose.psi_net_rad));
    EXPECT_FALSE(d.pose.reason.empty());
    EXPECT_TRUE(d.depths.empty());
    std::printf("noise frame: %s\n", d.pose.reason.c_str());
  }
  const auto flat = detector.detect(ImageU8(720, 540, 90));
  EXPECT_FALSE(flat.pose.valid());
  EXPECT_EQ(flat.pose.valid_rois, 0);
}

}  // namespace
}  // namespace pensight
