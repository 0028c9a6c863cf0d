// `pensight run --map` end to end: a rendered sequence through the pipeline with the mapping stage
// attached, its ground-truth depth integrated at the *estimated* camera poses, against the
// world's net surface.
#include <gtest/gtest.h>

#include <cstdio>

#include "mapping/map_accuracy.h"
#include "mapping/map_io.h"
#include "mapping/mapping_stage.h"
#include "sim/net_geometry.h"
#include "tests/support/rendered_run.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::mapping {
namespace {

TEST(RunMap, MapAtTheEstimatedPosesLiesOnTheNet) {
  const sim::Scenario s = testing::shipped_scenario("follow.yaml", 2.0);
  const testing::RenderedDataset rendered(s);
  const Dataset& d = rendered.dataset();
  MapConfig config;
  // A queue as deep as the sequence: this test is about where the map lies, not whether the
  // worker keeps pace with an offline run (how many frames a 2-deep queue drops depends on the
  // machine; mapping_stage_test covers the dropping).
  MappingStage stage(d.cam0.camera, config, d.frames.size());
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  options.write_published_global_pose = false;
  options.truth_depth = true;
  options.stages.push_back({[&](const FrameResult& r) { stage.push(r); },
                            [&] {
                              stage.finish();
                              write_map_outputs(stage.map(), rendered.dir() / "out");
                              return stage.stats();
                            }});
  const RunSummary summary =
      run_dataset(d, rendered.dir() / "out", options, testing::test_device());
  bool map_row = false;
  for (const TimingRow& row : summary.timing) map_row |= row.ours.name == "map";
  EXPECT_TRUE(map_row);
  const OccupancyMap loaded = read_map_vdb(rendered.dir() / "out" / "map.vdb");
  EXPECT_EQ(loaded.grid().activeVoxelCount(), stage.map().grid().activeVoxelCount());

  const MappingCounters c = stage.counters();
  EXPECT_EQ(c.integrated + c.dropped + c.without_pose + c.without_depth, d.frames.size());
  EXPECT_EQ(c.dropped, 0u);
  EXPECT_GT(c.integrated, d.frames.size() / 2);
  const sim::NetGeometry net(s.pen, s.net);
  // The surface the frames saw: their truth depth at their true camera poses.
  std::vector<Eigen::Vector3d> observed;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    const GroundTruthRow* truth = d.truth_for_frame(i);
    ASSERT_NE(truth, nullptr);
    Eigen::Isometry3d T_pen_body = Eigen::Isometry3d::Identity();
    T_pen_body.linear() = rotation_from_rpy(truth->roll_rad, truth->pitch_rad, truth->yaw_rad);
    T_pen_body.translation() = truth->p_pen_body_m;
    const Eigen::Isometry3d T_pen_camera = T_pen_body * d.cam0.T_body_camera;
    const ImageF32 depth = d.load_depth_m(i);
    for (int y = 4; y < depth.height; y += 9) {
      for (int x = 4; x < depth.width; x += 9) {
        const float z = depth.at(x, y);
        if (z > 0) observed.push_back(T_pen_camera * (d.cam0.camera.ray({x, y}) * z));
      }
    }
  }
  const MapAccuracy a = score_map(stage.map(), extract_surface(stage.map()), observed,
                                  [&](const Eigen::Vector3d& p) { return net.clearance(p); });
  std::printf("follow 2 s at the estimated poses, %zu frames integrated, %zu dropped: %s\n",
              c.integrated, c.dropped, describe(a, config.voxel_m).c_str());
  // The acceptance bounds of the ground-truth maps (map_accuracy_test): the estimated poses keep
  // the map within them. Measured: median 0.25 voxel, p95 0.67, completeness 99.9 %,
  // false occupancy 0.
  EXPECT_LE(a.median_m, 0.5 * config.voxel_m);
  EXPECT_LE(a.p95_m, 1.5 * config.voxel_m);
  EXPECT_GE(a.completeness, 0.95);
  EXPECT_LE(a.false_occupancy, 0.005);
}

}  // namespace
}  // namespace pensight::mapping
