// The mapping stage as the vehicle runtime uses it: it never makes push() wait, drops the oldest
// frame when behind, counts what it cannot map, and maps what it takes exactly as the integrator
// called directly.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <chrono>
#include <thread>

#include "core/error.h"
#include "mapping/mapping_stage.h"

namespace pensight::mapping {
namespace {

PinholeCamera camera() {
  PinholeCamera c;  // 720 x 540, fx 462
  return c;
}

// A wall facing the camera at z = d_m, and the camera moved along x by x_m.
std::shared_ptr<const ImageF32> wall(float d_m) {
  return std::make_shared<const ImageF32>(camera().width_px, camera().height_px, d_m);
}
Eigen::Isometry3d pose(double x_m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = x_m;
  return T;
}

// TBB is not instrumented for ThreadSanitizer, so its hand-offs (OpenVDB's own parallel loops
// included) read as races: one TBB thread, and TSan checks the stage's own threads.
const tbb::global_control one_tbb_thread(tbb::global_control::max_allowed_parallelism, 1);

TEST(MappingStage, PushNeverWaitsAndTheOldestFrameIsDropped) {
  MappingStage stage(camera(), MapConfig{});
  constexpr int kFrames = 40;
  std::vector<std::shared_ptr<const ImageF32>> walls;
  for (int i = 0; i < kFrames; ++i) walls.push_back(wall(1.0f + 0.01f * static_cast<float>(i)));
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kFrames; ++i) stage.push(i, walls[i], pose(0.05 * i));
  const double push_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  stage.finish();
  const MappingCounters c = stage.counters();
  EXPECT_EQ(c.integrated + c.dropped, static_cast<size_t>(kFrames));
  EXPECT_GT(c.dropped, 0u);
  const StageStats s = stage.stats();
  EXPECT_EQ(s.processed, c.integrated);
  EXPECT_EQ(s.dropped, c.dropped);
  // A push that waited for the integration would take a frame's integration time (several ms
  // for a 720 x 540 wall); all 40 pushes together take well under one.
  EXPECT_LT(push_ms, s.mean_ms) << "push() waited for the integration";
}

TEST(MappingStage, CountsFramesItCannotMap) {
  MappingStage stage(camera(), MapConfig{});
  FrameResult no_depth;
  no_depth.global_pose.T_pen_camera = pose(0);
  stage.push(no_depth);
  FrameResult no_pose;
  no_pose.depth_m = wall(1.0f);  // GlobalPose's T_pen_camera is NaN before the lock
  stage.push(no_pose);
  EXPECT_THROW(stage.map(), Error);
  stage.finish();
  const MappingCounters c = stage.counters();
  EXPECT_EQ(c.without_depth, 1u);
  EXPECT_EQ(c.without_pose, 1u);
  EXPECT_EQ(c.integrated, 0u);
  EXPECT_EQ(stage.map().grid().activeVoxelCount(), 0u);
  EXPECT_THROW(stage.push(1, wall(1.0f), pose(0)), Error);
}

TEST(MappingStage, MapsLikeTheIntegratorCalledDirectly) {
  MappingStage stage(camera(), MapConfig{});
  OccupancyMap direct(MapConfig{});
  ProjectiveIntegrator integrator(camera(), MapConfig{});
  for (int i = 0; i < 6; ++i) {
    const auto depth = wall(0.8f + 0.1f * static_cast<float>(i));
    stage.push(i, depth, pose(0.1 * i));
    integrator.integrate(direct, *depth, pose(0.1 * i));
    // One frame at a time, so none is dropped; read() sees the map while the stage runs.
    while (stage.counters().integrated < static_cast<size_t>(i + 1)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    size_t active = 0;
    stage.read([&](const OccupancyMap& m) { active = m.grid().activeVoxelCount(); });
    EXPECT_GT(active, 0u);
  }
  stage.finish();
  const openvdb::FloatGrid& a = stage.map().grid();
  const openvdb::FloatGrid& b = direct.grid();
  ASSERT_EQ(a.activeVoxelCount(), b.activeVoxelCount());
  auto acc = b.getConstAccessor();
  for (auto it = a.cbeginValueOn(); it; ++it) {
    ASSERT_TRUE(acc.isValueOn(it.getCoord()));
    ASSERT_EQ(*it, acc.getValue(it.getCoord()));
  }
}

}  // namespace
}  // namespace pensight::mapping
