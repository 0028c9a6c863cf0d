// Marine snow is a particle field fixed in the water: with the camera and the water still, the
// same spots come back every frame; a current moves every spot the same way; the density is
// the configured number of particles in view.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/marine_snow.h"
#include "sim/render_cpu.h"
#include "tests/sim/sim_test_scenes.h"

namespace pensight::sim {
namespace {

Scenario still_camera(const Eigen::Vector3d& current_mps, double density = 0.3) {
  Scenario s = testing::one_pose({.net_distance_m = 2.0}, 720, 540);
  s.water.current_mps = current_mps;
  s.water.marine_snow = density;
  s.camera.samples_per_axis = 1;
  return s;
}

TEST(MarineSnow, StillWaterAndCameraGiveTheSameSpotsEveryFrame) {
  const Scenario s = still_camera(Eigen::Vector3d::Zero());
  const auto a = snow_spots(s, frame_state(s, 0)), b = snow_spots(s, frame_state(s, 7));
  ASSERT_GT(a.size(), 20u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x_px, b[i].x_px);
    EXPECT_EQ(a[i].y_px, b[i].y_px);
  }
}

TEST(MarineSnow, CurrentAcrossTheViewMovesEverySpotSideways) {
  // The camera faces the net at along 0: its x axis is +y in P. A 0.2 m/s current along +y
  // carries every particle 2 cm to the right per 0.1 s frame: fx * 0.02 / z px at depth z.
  const Scenario s = still_camera({0, 0.2, 0});
  const auto a = snow_spots(s, frame_state(s, 0)), b = snow_spots(s, frame_state(s, 1));
  const double fx = s.camera.calibration.camera.fx_px;
  size_t matched = 0, inside = 0;
  for (const SnowSpot& p : a) {
    if (p.x_px < 100 || p.x_px > 600) continue;  // its partner stays in view
    ++inside;
    for (const SnowSpot& q : b) {
      // Same particle: same row and size (its depth in the camera frame is unchanged).
      if (std::abs(q.y_px - p.y_px) > 1e-6 || std::abs(q.sigma_px - p.sigma_px) > 1e-9) continue;
      const double dx = q.x_px - p.x_px;
      EXPECT_GT(dx, fx * 0.02 / kSnowFar_m - 1e-6);
      EXPECT_LT(dx, fx * 0.02 / kSnowNear_m + 1e-6);
      ++matched;
    }
  }
  EXPECT_GT(inside, 20u);
  EXPECT_EQ(matched, inside);
}

TEST(MarineSnow, ParticlesInViewMatchTheDensity) {
  // marine_snow is the expected number in view per 24x24 px of the 720x540 reference camera.
  const Scenario s = still_camera(Eigen::Vector3d::Zero(), 0.2);
  const double expected = 0.2 * 720 * 540 / (24.0 * 24.0);
  double sum = 0;
  const int frames = 20;
  for (int i = 0; i < frames; ++i) {
    // A new stretch of water each frame: the camera stays, the current carries 1 m past it.
    Scenario moving = s;
    moving.water.current_mps = {0, 10.0, 0};
    int in_image = 0;
    for (const SnowSpot& p : snow_spots(moving, frame_state(moving, i))) {
      in_image += p.x_px >= -0.5 && p.x_px < 719.5 && p.y_px >= -0.5 && p.y_px < 539.5;
    }
    sum += in_image;
  }
  const double mean = sum / frames;
  std::printf("  particles in view: %.1f per frame, expected %.1f\n", mean, expected);
  EXPECT_NEAR(mean / expected, 1.0, 0.15);
}

TEST(MarineSnow, SpotsAppearInTheImage) {
  Scenario s = still_camera(Eigen::Vector3d::Zero());
  const NetGeometry net(s.pen, s.net);
  const FrameState f = frame_state(s, 0);
  const RenderedFrame with = render_cpu(s, net, f, {.noise = false, .marine_snow = true});
  const RenderedFrame without = render_cpu(s, net, f, {.noise = false, .marine_snow = false});
  int brighter = 0;
  for (const SnowSpot& p : snow_spots(s, f)) {
    const int x = static_cast<int>(std::lround(p.x_px)), y = static_cast<int>(std::lround(p.y_px));
    if (x < 0 || y < 0 || x >= 720 || y >= 540 || p.peak * 255 * s.camera.exposure < 3) continue;
    brighter += with.image.at(x, y) > without.image.at(x, y) + 1;
  }
  EXPECT_GT(brighter, 10);
}

}  // namespace
}  // namespace pensight::sim
