// A mesh finer than the planned grid's resampled ROIs hold (fine_mesh_probe.h): on a 1280x720
// camera the grid is 533 px ROIs at FFT 256, which read up to 56 periods across (9.5 px). A finer
// lattice (below 4.6 px: folded back into the band as a coarser one) is named by the probe and the
// detector analyses the frame on native 256 px ROIs, which read its true distance. Coarser
// lattices and grids that do not resample are left alone.
#include "pipeline/fft/fine_mesh_probe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <string>

#include "pipeline/fft/net_detector.h"
#include "tests/support/test_seed.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

// Twines along both axes with a random phase, slightly rotated, and read noise.
ImageU8 lattice_image(int w, int h, double period_px, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> phase(0, 2 * std::numbers::pi), turn(-0.1, 0.1);
  std::normal_distribution<double> noise(0, 2);
  const double p1 = phase(rng), p2 = phase(rng), a = turn(rng);
  const double k = 2 * std::numbers::pi / period_px, c = std::cos(a), s = std::sin(a);
  ImageU8 image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double u = c * x + s * y, v = -s * x + c * y;
      const double g = 110 + 50 * (std::cos(k * u + p1) + std::cos(k * v + p2)) + noise(rng);
      image.at(x, y) = static_cast<uint8_t>(std::clamp(g, 0.0, 255.0));
    }
  }
  return image;
}

double period_in(const std::string& reason) {
  return std::stod(reason.substr(reason.find("mesh period ") + 12));
}

NetDetectorConfig cpu_config() {
  NetDetectorConfig c;
  c.backend = Backend::kCpu;
  c.cpu_threads = 1;
  return c;
}

TEST(FineMeshProbe, ALatticeFinerThanTheGridHoldsIsReadOnNativeRois) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera camera = default_field_of_view(1280, 720);
  NetDetectorConfig config = cpu_config();
  NetDetector detector(camera, config, testing::test_device());
  ASSERT_EQ(detector.config().grid.roi_size_px, 533);
  ASSERT_EQ(detector.config().fft_size, 256);
  const double period_px = std::uniform_real_distribution<double>(2.8, 9.2)(rng);
  const ImageU8 image = lattice_image(1280, 720, period_px, rng);

  FineMeshProbe probe({.width = 1280, .height = 720, .roi_size_px = 533}, {},
                      config.points.min_quality);
  const std::optional<std::string> why = probe.too_fine(image);
  ASSERT_TRUE(why);
  EXPECT_NEAR(period_in(*why), period_px, 0.1) << *why;
  EXPECT_NE(why->find("too fine for ROIs of 533 px analysed at FFT 256 ("), std::string::npos)
      << *why;
  EXPECT_NE(why->find(" periods across, at most 56); analysed on ROIs of 256 px"),
            std::string::npos)
      << *why;

  // The bars' true distance: fx x bar / period (the lattice is frontal).
  const double truth_m = camera.fx_px * detector.config().bar_length_m / period_px;
  const NetDetection d = detector.detect(image);
  EXPECT_EQ(d.roi_size_px, 256);
  EXPECT_EQ(d.rois.size(), d.points.size());
  ASSERT_TRUE(d.pose.valid()) << d.pose.reason;
  std::printf("period %.2f px: d_net %.3f m, truth %.3f m\n", period_px, d.pose.d_net_m, truth_m);
  EXPECT_NEAR(d.pose.d_net_m / truth_m, 1.0, 0.02);
}

TEST(FineMeshProbe, CoarserLatticesAndGridsThatDoNotResampleAreLeftAlone) {
  std::mt19937_64 rng(testing::fresh_seed());
  const kernels::FftRoiShape resampled{.width = 1280, .height = 720, .roi_size_px = 533};
  FineMeshProbe probe(resampled, {}, 0.03);
  const double coarse_px = std::uniform_real_distribution<double>(9.8, 40)(rng);
  EXPECT_FALSE(probe.too_fine(lattice_image(1280, 720, coarse_px, rng))) << coarse_px;
  EXPECT_FALSE(probe.too_fine(ImageU8(1280, 720, 90)));  // no net
  // 256 px ROIs at FFT 256 see a 3 px lattice at its own pixels: nothing folds.
  FineMeshProbe native({.width = 1280, .height = 720, .roi_size_px = 256}, {}, 0.03);
  EXPECT_FALSE(native.too_fine(lattice_image(1280, 720, 3.0, rng)));
}

// A net held near the limit is not read on alternating grids: after a native frame the planned
// grid returns only below 85 % of the limit (48 of 56 periods across 533 px: 11.2 px).
TEST(FineMeshProbe, ANetNearTheLimitStaysOnOneGrid) {
  std::mt19937_64 rng(testing::fresh_seed());
  FineMeshProbe probe({.width = 1280, .height = 720, .roi_size_px = 533}, {}, 0.03);
  const double near_limit_px = std::uniform_real_distribution<double>(9.8, 10.8)(rng);
  EXPECT_FALSE(probe.too_fine(lattice_image(1280, 720, near_limit_px, rng))) << near_limit_px;
  ASSERT_TRUE(probe.too_fine(lattice_image(1280, 720, 6.0, rng)));
  const std::optional<std::string> why =
      probe.too_fine(lattice_image(1280, 720, near_limit_px, rng));
  ASSERT_TRUE(why) << near_limit_px;
  EXPECT_NE(why->find("at most 48)"), std::string::npos) << *why;
  EXPECT_FALSE(probe.too_fine(ImageU8(1280, 720, 90)));  // no lattice: the planned grid
  const double coarser_px = std::uniform_real_distribution<double>(11.6, 14)(rng);
  EXPECT_FALSE(probe.too_fine(lattice_image(1280, 720, coarser_px, rng))) << coarser_px;
  EXPECT_FALSE(probe.too_fine(lattice_image(1280, 720, near_limit_px, rng))) << near_limit_px;
}

}  // namespace
}  // namespace pensight
