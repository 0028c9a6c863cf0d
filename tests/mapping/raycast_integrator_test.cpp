// The plain ray-casting integrator on one small synthetic frame seen from the origin (camera axes
// = P axes): a wall at 1 m in the left third of the image, no measurement in the middle third,
// depths beyond max range in the right third. Log-odds are sums of the config's exact float
// steps, so they are compared exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "mapping/raycast_integrator.h"

namespace pensight::mapping {
namespace {

struct Frame {
  PinholeCamera cam = PinholeCamera{}.scaled(0.1);  // 72 x 54
  ImageF32 depth_m{cam.width_px, cam.height_px, 0.0f};
  Frame() {
    for (int y = 0; y < cam.height_px; ++y) {
      for (int x = 0; x < cam.width_px; ++x) {
        depth_m.at(x, y) = x < 24 ? 1.0f : (x < 48 ? 0.0f : 10.0f);
      }
    }
  }
  Eigen::Vector3d point(int x, int y, double z_m) const {
    return cam.ray(Eigen::Vector2d(x, y)) * z_m;
  }
};

TEST(RaycastIntegrator, HitsAtTheDepthMissesInFrontUnknownElsewhere) {
  const Frame fr;
  const MapConfig config;
  OccupancyMap map(config);
  RaycastIntegrator integrator(fr.cam, config);
  const auto hit = static_cast<float>(config.hit_log_odds);
  const auto miss = static_cast<float>(config.miss_log_odds);

  const IntegrationStats st = integrator.integrate(map, fr.depth_m, Eigen::Isometry3d::Identity());
  ASSERT_TRUE(st.integrated);
  // Every measured point's voxel is a hit, even where another pixel's ray crosses it.
  for (int y = 0; y < fr.cam.height_px; ++y) {
    for (int x = 0; x < 24; ++x) EXPECT_EQ(map.log_odds_at(fr.point(x, y, 1.0)), hit);
  }
  // Once per voxel and frame: each active voxel holds exactly one hit or one miss, and the voxels
  // next to the camera, crossed by every ray, one miss.
  size_t hits = 0;
  for (auto it = map.grid().cbeginValueOn(); it; ++it) {
    ASSERT_TRUE(*it == hit || *it == miss) << *it << " at " << it.getCoord();
    hits += *it == hit;
  }
  EXPECT_EQ(hits, st.hit_voxels);
  EXPECT_EQ(map.log_odds_at(fr.point(12, 27, 0.05)), miss);
  EXPECT_EQ(map.log_odds_at(fr.point(12, 27, 0.5)), miss);
  EXPECT_EQ(map.log_odds_at(fr.point(12, 27, 1.2)), 0.0f);  // behind the wall
  EXPECT_EQ(map.log_odds_at(fr.point(36, 27, 0.5)), 0.0f);  // no measurement
  EXPECT_EQ(map.log_odds_at(fr.point(60, 27, 4.0)), miss);  // beyond max range: cleared to it
  EXPECT_EQ(map.log_odds_at(fr.point(60, 27, 5.5)), 0.0f);
  EXPECT_EQ(map.occupancy_at(fr.point(60, 27, 4.0)), Occupancy::kFree);

  integrator.integrate(map, fr.depth_m, Eigen::Isometry3d::Identity());
  EXPECT_EQ(map.log_odds_at(fr.point(12, 27, 1.0)), hit + hit);
  EXPECT_EQ(map.log_odds_at(fr.point(12, 27, 0.5)), miss + miss);
}

TEST(RaycastIntegrator, SkipsANanPoseAndRefusesAWrongImageSize) {
  const Frame fr;
  const MapConfig config;
  OccupancyMap map(config);
  RaycastIntegrator integrator(fr.cam, config);
  Eigen::Isometry3d nan_pose = Eigen::Isometry3d::Identity();
  nan_pose.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(integrator.integrate(map, fr.depth_m, nan_pose).integrated);
  EXPECT_EQ(map.grid().activeVoxelCount(), 0u);
  EXPECT_THROW(integrator.integrate(map, ImageF32(10, 10, 1.0f), Eigen::Isometry3d::Identity()),
               Error);
}

}  // namespace
}  // namespace pensight::mapping
