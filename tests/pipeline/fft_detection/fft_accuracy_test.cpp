// Accuracy of the whole FFT stage (CPU path) on rendered planar nets against their known truth.
#include <gtest/gtest.h>

#include <random>

#include "core/units.h"
#include "tests/pipeline/fft_detection/sweep.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::NetScene;

using testing::render_all;

TEST(FftAccuracy, SweepMeetsBounds) {
  const PinholeCamera cam{.k1 = -0.04, .k2 = 0.01};
  const auto scenes = testing::sweep_scenes(24, testing::fresh_seed(), {});
  const auto frames = render_all(cam, scenes);
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  const auto e = testing::run_sweep(frames, scenes, detector, true);
  testing::print_errors("default", e);
  EXPECT_EQ(e.invalid, 0);
  EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.02);
  EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 1.0);
}

// Turbid water (contrast halves every ~0.7 m) and low light (dark, noisy, low contrast).
// Turbid psi errors are heavy-tailed (the far side of an oblique net fades): over 227 frames the
// error was 0.26 deg median, 1.48 at p90, 4.17 at worst, and the median of 12 frames exceeded
// 1 deg in 2 of 102 runs (seeds 87, 102). Resampling those frames, the median of 24 exceeds
// 1.25 deg once in ~50000 runs; low light's median of 12 exceeds 1 deg once in ~30000.
// A turbid frame has no pose about once in 150 (6 of 912 frames, seeds 1-38; low light 0 of 456):
// 2 of 24 happens in ~1 % of runs, 4 of 24 in ~2e-5.
TEST(FftAccuracy, TurbidAndLowLight) {
  const PinholeCamera cam;
  const uint64_t seed = testing::fresh_seed();
  struct Case {
    const char* label;
    NetScene base;
    int frames;
    int max_invalid;
    double psi_median_deg;
  };
  for (const Case& c :
       {Case{"turbid",
             {.net_level = 150, .water_level = 90, .attenuation_m = 1.0, .noise_sigma = 4},
             24,
             3,
             1.25},
        Case{"low light", {.net_level = 40, .water_level = 15, .noise_sigma = 6}, 12, 1, 1.0}}) {
    const auto scenes = testing::sweep_scenes(c.frames, seed, c.base);
    NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
    const auto e = testing::run_sweep(render_all(cam, scenes), scenes, detector, true);
    testing::print_errors(c.label, e);
    EXPECT_LE(e.invalid, c.max_invalid) << c.label;
    EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.02) << c.label;
    EXPECT_LE(testing::percentile(e.psi_deg, 0.5), c.psi_median_deg) << c.label;
  }
}

// Frames without a net must give NaN and a reason, never a number.
TEST(FftAccuracy, NoNetGivesNanWithReason) {
  const PinholeCamera cam;
  std::mt19937_64 rng(testing::fresh_seed());
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
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

// Beyond the specified envelope (too far, too oblique): NaN with a reason, or a distance still
// within 20% of the truth, never a wrong number. Over seeds 1-900 this failed 2 % of runs before
// the extrapolation, tilt-agreement and beyond-band rules (docs/fft_detection.md, "Beyond the
// envelope").
TEST(FftAccuracy, OutsideTheEnvelopeNoWrongDistances) {
  const PinholeCamera cam;
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> far(3.0, 8.0), oblique(55, 80), sign(-1, 1);
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  for (int i = 0; i < 12; ++i) {
    NetScene s{.noise_sigma = 3, .seed = rng()};
    if (i % 2) {
      s.distance_m = far(rng);
    } else {
      s.distance_m = 1.0;
      s.psi_rad = deg_to_rad((sign(rng) < 0 ? -1 : 1) * oblique(rng));
    }
    const NetDetection d = detector.detect(testing::render_net(cam, s));
    if (!d.pose.valid()) {
      EXPECT_FALSE(d.pose.reason.empty());
      continue;
    }
    EXPECT_LE(std::abs(d.pose.d_net_m - s.distance_m), 0.2 * s.distance_m)
        << "d " << s.distance_m << " psi " << rad_to_deg(s.psi_rad) << ": estimate "
        << d.pose.d_net_m << " m, psi " << rad_to_deg(d.pose.psi_net_rad) << " deg from "
        << d.pose.inlier_rois << " of " << d.pose.valid_rois << " valid ROIs";
  }
}

// The net ends right of the image centre: the ROIs that see only water must be rejected.
TEST(FftAccuracy, HalfNetFramesRejectTheEmptyRois) {
  const PinholeCamera cam;
  // The third ROI column is part water and biases the range of half nets. Over 61 seeds of 16
  // frames the run's median range error was 1.34 % typically, 2.10 % at the 95th percentile and
  // 2.50 % at worst (seed 2), psi 0.94 / 1.30 / 1.49 deg; NaN frames (with a reason) 0 in 54
  // runs, 1 in 6, 2 in 1 (about 0.7 % of frames).
  const auto scenes =
      testing::sweep_scenes(16, testing::fresh_seed(), {.noise_sigma = 4, .edge_m = 0.0});
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  const auto e = testing::run_sweep(render_all(cam, scenes), scenes, detector, true);
  testing::print_errors("half net", e);
  EXPECT_LE(e.invalid, 3);
  EXPECT_LE(testing::percentile(e.d_rel, 0.5), 0.03);
  EXPECT_LE(testing::percentile(e.psi_deg, 0.5), 2.5);
  EXPECT_LE(testing::percentile(e.d_rel, 1.0), 0.2);  // no wrong distance
}

}  // namespace
}  // namespace pensight
