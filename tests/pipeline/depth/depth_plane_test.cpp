// The robust plane over a dense depth image: exact on a plane, unmoved by 25 % of outlier pixels
// (a fish), NaN with a reason when too little of the image has depth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "pipeline/depth/depth_plane.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

ImageF32 plane_depth(const PinholeCamera& cam, double c, double a, double b) {
  ImageF32 d(cam.width_px, cam.height_px);
  for (int v = 0; v < d.height; ++v) {
    for (int u = 0; u < d.width; ++u) {
      const Eigen::Vector3d r = cam.ray({u, v});
      d.at(u, v) = static_cast<float>(c / (1 - a * r.x() - b * r.y()));
    }
  }
  return d;
}

TEST(DepthPlane, RecoversThePlaneDespiteAFish) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<> u(-1, 1);
  const PinholeCamera cam = PinholeCamera{.k1 = -0.04}.scaled(320.0 / 720);
  const PixelRays rays(cam);
  for (int trial = 0; trial < 10; ++trial) {
    const double c = 1.5 + u(rng), a = 0.6 * u(rng), b = 0.3 * u(rng);
    ImageF32 d = plane_depth(cam, c, a, b);
    // A "fish": a block of a quarter of the image half way to the camera, off the centre.
    for (int v = 0; v < 120; ++v) {
      for (int x = 0; x < 160; ++x) d.at(x, v) *= 0.5f;
    }
    // d_net: the mean depth of the net pixels in the central 20 % window (the fish left out).
    double window_sum = 0;
    int window_count = 0;
    for (int v = 0; v < d.height; ++v) {
      for (int x = 0; x < d.width; ++x) {
        const bool fish = v < 120 && x < 160;
        if (fish || std::abs(x - cam.cx_px) > 0.1 * d.width ||
            std::abs(v - cam.cy_px) > 0.1 * d.height)
          continue;
        window_sum += d.at(x, v);
        ++window_count;
      }
    }
    const double window_mean = window_sum / window_count;
    d.at(5, 5) = std::nanf("");
    d.at(6, 5) = 0;
    const DepthPlanePose p = depth_plane_pose(d, rays);
    ASSERT_TRUE(p.valid()) << p.reason;
    EXPECT_NEAR(p.psi_net_rad, std::atan(a), 1e-3);
    EXPECT_NEAR(p.pitch_net_rad, std::atan(b), 1e-3);
    EXPECT_NEAR(p.d_net_m, window_mean, 1e-4 * window_mean);
    EXPECT_NEAR(p.inlier_share, 0.75, 0.02);
  }
}

TEST(DepthPlane, TooLittleDepthAndWrongSize) {
  const PinholeCamera cam = PinholeCamera{}.scaled(320.0 / 720);
  ImageF32 d(cam.width_px, cam.height_px, 0.0f);
  for (int u = 0; u < 50; ++u) d.at(u, 10) = 1.0f;
  const DepthPlanePose p = depth_plane_pose(d, PixelRays(cam));
  EXPECT_FALSE(p.valid());
  EXPECT_TRUE(std::isnan(p.psi_net_rad));
  EXPECT_THROW(depth_plane_pose(ImageF32(10, 10), PixelRays(cam)), Error);
}

}  // namespace
}  // namespace pensight
