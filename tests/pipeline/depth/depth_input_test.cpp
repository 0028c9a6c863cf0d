// The network's inputs: area resize against a direct box average, and priors moved into the
// network's pixels (a camera pixel centre lands on the same scene point), capped by quality.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/error.h"
#include "pipeline/depth/depth_input.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

TEST(DepthInput, ResizeAreaIsTheBoxMean) {
  std::mt19937_64 rng(testing::fresh_seed());
  ImageU8 image(720, 540);
  for (auto& p : image.pixels) p = static_cast<uint8_t>(rng() % 256);
  const ImageU8 small = resize_area(image, 320, 240);
  ASSERT_EQ(small.width, 320);
  ASSERT_EQ(small.height, 240);
  // 720 / 320 = 2.25: output pixel (x, y) covers input [2.25 x, 2.25 (x + 1)), weights by overlap.
  auto box = [&](int x, int y) {
    double sum = 0, weight = 0;
    for (int v = 0; v < 540; ++v) {
      const double wy =
          std::max(0.0, std::min(v + 1.0, 2.25 * (y + 1)) - std::max(v * 1.0, 2.25 * y));
      if (wy == 0) continue;
      for (int u = 0; u < 720; ++u) {
        const double wx =
            std::max(0.0, std::min(u + 1.0, 2.25 * (x + 1)) - std::max(u * 1.0, 2.25 * x));
        sum += wx * wy * image.at(u, v);
        weight += wx * wy;
      }
    }
    return sum / weight;
  };
  for (int i = 0; i < 50; ++i) {
    const int x = static_cast<int>(rng() % 320), y = static_cast<int>(rng() % 240);
    EXPECT_NEAR(small.at(x, y), box(x, y), 1.0) << x << ", " << y;
  }
  EXPECT_THROW(resize_area(ImageU8(), 320, 240), Error);
  EXPECT_THROW(resize_area(image, 0, 240), Error);
}

TEST(DepthInput, NetworkDepthsScaleAboutPixelCentresAndKeepTheBest) {
  std::vector<SparseDepth> depths = {
      {{0, 0, 1.0f}, 0.5f}, {{719, 539, 2.0f}, 0.2f}, {{359.5f, 269.5f, 3.0f}, 0.1f}};
  const auto pts = points_of(network_depths(depths, {0, 0, 720, 540}, 320, 240));
  ASSERT_EQ(pts.size(), 3u);
  EXPECT_NEAR(pts[0].x_px, 0.5 * 320 / 720 - 0.5, 1e-6);
  EXPECT_NEAR(pts[1].y_px, 539.5 * 240 / 540 - 0.5, 1e-4);
  EXPECT_NEAR(pts[2].x_px, 159.5, 1e-4);  // the image centre stays the centre
  EXPECT_EQ(pts[2].depth_m, 3.0f);
  EXPECT_EQ(network_depths(depths, {0, 0, 720, 540}, 320, 240)[1].quality, 0.2f);

  std::vector<SparseDepth> many(kernels::kMaxSparsePoints + 10);
  for (size_t i = 0; i < many.size(); ++i) {
    many[i] = {{static_cast<float>(i % 720), 10, static_cast<float>(i)},
               i < 10 ? 0.0f : 1.0f};  // the first ten are the worst
  }
  const auto kept = network_depths(many, {0, 0, 720, 540}, 320, 240);
  ASSERT_EQ(kept.size(), static_cast<size_t>(kernels::kMaxSparsePoints));
  EXPECT_EQ(kept.front().point.depth_m, 10.0f);  // order kept, the ten worst dropped
}

// The network's view of a camera of another aspect: the centred crop of the network's aspect, the
// camera's intrinsics and the priors moved with it, priors outside dropped.
TEST(DepthInput, AnotherAspectIsSeenThroughTheCentredCrop) {
  const auto expect_view = [](NetworkView v, int x0, int y0, int w, int h) {
    EXPECT_EQ(v.x0_px, x0);
    EXPECT_EQ(v.y0_px, y0);
    EXPECT_EQ(v.width_px, w);
    EXPECT_EQ(v.height_px, h);
  };
  expect_view(network_view(720, 540, 320, 240), 0, 0, 720, 540);
  expect_view(network_view(1920, 1080, 320, 240), 240, 0, 1440, 1080);
  expect_view(network_view(640, 480, 512, 288), 0, 60, 640, 360);
  expect_view(network_view(336, 189, 320, 240), 42, 0, 252, 189);
  expect_view(network_view(1000, 1000, 320, 240), 0, 125, 1000, 750);
  EXPECT_THROW(network_view(0, 480, 320, 240), Error);

  PinholeCamera wide;
  wide.width_px = 960;
  wide.cx_px = 479.5;
  const NetworkView v = network_view(960, 540, 320, 240);
  const PinholeCamera seen = network_camera(wide, v, 320, 240);
  const PinholeCamera reference = PinholeCamera{}.scaled(320.0 / 720.0);
  EXPECT_EQ(seen.width_px, 320);
  EXPECT_EQ(seen.height_px, 240);
  EXPECT_NEAR(seen.fx_px, reference.fx_px, 1e-12);
  EXPECT_NEAR(seen.cx_px, reference.cx_px, 1e-12);
  EXPECT_NEAR(seen.cy_px, reference.cy_px, 1e-12);

  const std::vector<SparseDepth> depths = {
      {{100, 200, 1.0f}, 1}, {{120, 0, 2.0f}, 1}, {{839, 539, 3.0f}, 1}, {{840, 100, 4.0f}, 1}};
  const auto got = network_depths(depths, v, 320, 240);
  ASSERT_EQ(got.size(), 2u);  // x 100 and 840 lie outside the crop [120, 840)
  EXPECT_EQ(got[0].point.depth_m, 2.0f);
  EXPECT_NEAR(got[0].point.x_px, (0 + 0.5) * 320.0 / 720 - 0.5, 1e-5);
  EXPECT_NEAR(got[1].point.x_px, (719 + 0.5) * 320.0 / 720 - 0.5, 1e-5);
  EXPECT_NEAR(got[1].point.y_px, (539 + 0.5) * 240.0 / 540 - 0.5, 1e-5);

  // The crop's pixels, area-resized.
  ImageU8 image(960, 540, 0);
  for (int y = 0; y < 540; ++y)
    for (int x = 120; x < 840; ++x) image.at(x, y) = 200;
  const ImageU8 small = network_image(image, v, 320, 240);
  EXPECT_TRUE(
      std::all_of(small.pixels.begin(), small.pixels.end(), [](uint8_t p) { return p == 200; }));
}

}  // namespace
}  // namespace pensight
