// The map of whole shipped sequences, integrated from ground-truth depth and poses, against the
// world's net surface. PENSIGHT_MAP_FULL=1 maps every frame at the camera's resolution (the
// figures in docs/mapping.md); by default every frame at half resolution.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "mapping/map_accuracy.h"
#include "mapping/map_io.h"
#include "mapping/projective_integrator.h"
#include "sim/frame_state.h"
#include "sim/truth_depth.h"
#include "tests/support/rendered_run.h"

namespace pensight::mapping {
namespace {

struct SequenceResult {
  MapAccuracy accuracy;
  double mean_ms = 0, max_ms = 0;
  size_t memory_bytes = 0;
};

SequenceResult map_sequence(const std::string& file) {
  const bool full = std::getenv("PENSIGHT_MAP_FULL") != nullptr;
  const sim::Scenario s = testing::shipped_scenario(file);
  const sim::NetGeometry net(s.pen, s.net);
  const PinholeCamera cam = s.camera.calibration.camera.scaled(full ? 1.0 : 0.5);
  MapConfig config;
  OccupancyMap map(config);
  ProjectiveIntegrator integrator(cam, config);
  std::vector<Eigen::Vector3d> observed;
  SequenceResult r;
  const int frames = s.num_frames();
  for (int f = 0; f < frames; ++f) {
    const sim::FrameState fs = sim::frame_state(s, f);
    const ImageF32 depth = sim::truth_depth(s, net, cam, fs.T_pen_camera);
    const auto t0 = std::chrono::steady_clock::now();
    integrator.integrate(map, depth, fs.T_pen_camera);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    r.mean_ms += ms / frames;
    r.max_ms = std::max(r.max_ms, ms);
    for (int y = 3; y < cam.height_px; y += 7) {
      for (int x = 3; x < cam.width_px; x += 7) {
        const float d = depth.at(x, y);
        if (d > 0 && d <= config.max_range_m) {
          observed.push_back(fs.T_pen_camera * (cam.ray(Eigen::Vector2d(x, y)) * d));
        }
      }
    }
  }
  const SurfaceMesh mesh = extract_surface(map);
  r.accuracy =
      score_map(map, mesh, observed, [&](const Eigen::Vector3d& p) { return net.clearance(p); });
  r.memory_bytes = map.memory_bytes();
  std::printf("%s (%d frames, %dx%d): %s; integration mean %.1f ms, max %.1f ms; map %.1f MB\n",
              file.c_str(), frames, cam.width_px, cam.height_px,
              describe(r.accuracy, config.voxel_m).c_str(), r.mean_ms, r.max_ms,
              static_cast<double>(r.memory_bytes) / 1e6);
  return r;
}

class MapAccuracyTest : public ::testing::TestWithParam<const char*> {};

TEST_P(MapAccuracyTest, MeshLiesOnTheNet) {
  const SequenceResult r = map_sequence(GetParam());
  const double v = MapConfig{}.voxel_m;
  EXPECT_LE(r.accuracy.median_m, 0.5 * v);
  EXPECT_LE(r.accuracy.p95_m, 1.5 * v);
  EXPECT_GE(r.accuracy.completeness, 0.95);
  EXPECT_LE(r.accuracy.false_occupancy, 0.005);
}

INSTANTIATE_TEST_SUITE_P(Sequences, MapAccuracyTest,
                         ::testing::Values("follow.yaml", "lawnmower.yaml", "sweep.yaml",
                                           "tank.yaml"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace pensight::mapping
