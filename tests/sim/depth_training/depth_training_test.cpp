// The depth network's training data: random scenes that validate, samples whose FFT priors agree
// with the rendered ground truth, and the folder layout scripts/train_depth.py reads.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "core/error.h"
#include "sim/depth_training.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::sim {
namespace {
namespace fs = std::filesystem;

TEST(DepthTraining, RandomScenesValidateAndVary) {
  std::mt19937_64 rng(testing::fresh_seed());
  int planes = 0, diamonds = 0, with_fish = 0;
  double nearest = 1e9, farthest = 0;
  for (int i = 0; i < 300; ++i) {
    const Scenario s = random_depth_scene(rng());  // validate() runs inside
    ASSERT_EQ(s.num_frames(), 1);
    planes += s.pen.shape == NetShape::kPlane;
    diamonds += s.net.mesh_type == MeshType::kDiamond;
    with_fish += !s.fish.empty();
    const double d = s.waypoints[0].net_distance_m - 0.3;
    nearest = std::min(nearest, d);
    farthest = std::max(farthest, d);
  }
  EXPECT_GT(planes, 15);
  EXPECT_GT(diamonds, 80);
  EXPECT_GT(with_fish, 30);
  EXPECT_LT(nearest, 0.4);
  EXPECT_GT(farthest, 3.5);
}

// The priors are the detector's, so they carry its noise; but on the rendered net most must lie
// within 5 % of the truth at their own pixel. Misplaced or misscaled priors give a share near 0
// in every sample. The detector's own wrong frame does so in one sample of about 25 (seeds
// 1-125, 250 samples: shares 0, 0, 0.24, 0.34, 0.37, then 0.52 and up, 0.95 typically), so the
// better of the two samples is held: its lowest over those seeds was 0.70.
TEST(DepthTraining, SamplePriorsMatchTheRenderedDepth) {
  std::mt19937_64 rng(testing::fresh_seed());
  int samples_with_priors = 0;
  double best_share = 0;
  for (int attempt = 0; attempt < 12 && samples_with_priors < 2; ++attempt) {
    const DepthSample s = make_depth_sample(rng(), 320, 240);
    ASSERT_EQ(s.image.width, 320);
    ASSERT_EQ(s.depth_mm.height, 240);
    if (s.points.empty()) continue;
    ++samples_with_priors;
    int close = 0, compared = 0;
    for (const SparseDepth& p : s.points) {
      const int x = static_cast<int>(std::floor(p.point.x_px + 0.5));
      const int y = static_cast<int>(std::floor(p.point.y_px + 0.5));
      ASSERT_TRUE(x >= 0 && y >= 0 && x < 320 && y < 240) << p.point.x_px << ", " << p.point.y_px;
      const double truth_m = s.depth_mm.at(x, y) * 1e-3;
      if (truth_m == 0) continue;  // a fish or the water at that pixel
      ++compared;
      close += std::abs(p.point.depth_m - truth_m) < 0.05 * truth_m;
    }
    ASSERT_GT(compared, 0);
    std::printf("priors within 5 %% of the truth: %d of %d\n", close, compared);
    best_share = std::max(best_share, static_cast<double>(close) / compared);
  }
  EXPECT_EQ(samples_with_priors, 2);
  EXPECT_GE(best_share, 0.5);
}

TEST(DepthTraining, FolderLayoutAndRefusals) {
  const fs::path dir =
      fs::temp_directory_path() / ("pensight_depth_training_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  write_depth_data(dir / "data", {.samples = 3, .seed = testing::fresh_seed(), .threads = 2});
  const size_t pixels = 320 * 240;
  EXPECT_EQ(fs::file_size(dir / "data" / "image.u8"), 3 * pixels);
  EXPECT_EQ(fs::file_size(dir / "data" / "depth_mm.u16"), 3 * pixels * 2);
  EXPECT_EQ(fs::file_size(dir / "data" / "points.f32"), 3u * 1024 * 4 * 4);
  EXPECT_EQ(fs::file_size(dir / "data" / "num_points.i32"), 3u * 4);
  ASSERT_EQ(fs::file_size(dir / "data" / "wall.f32"), 3u * 2 * 4);
  // Each scene's wall: a pen of 6-25 m or a flat panel, the camera's 462 px at 720 -> 320 px.
  std::ifstream wall_file(dir / "data" / "wall.f32", std::ios::binary);
  float walls[6];
  wall_file.read(reinterpret_cast<char*>(walls), sizeof(walls));
  for (int i = 0; i < 3; ++i) {
    const float curvature = walls[2 * i];
    EXPECT_TRUE(curvature == 0 || (curvature >= 1 / 25.0f && curvature <= 1 / 6.0f)) << curvature;
    EXPECT_NEAR(walls[2 * i + 1], 462.0 * 320 / 720, 1e-3);
  }
  std::ifstream meta(dir / "data" / "depth_data.txt");
  std::stringstream text;
  text << meta.rdbuf();
  EXPECT_NE(text.str().find("samples: 3\n"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("version: 2\n"), std::string::npos) << text.str();
  // Rewriting replaces the earlier data; a folder of something else is never replaced.
  write_depth_data(dir / "data", {.samples = 1, .threads = 1});
  EXPECT_EQ(fs::file_size(dir / "data" / "image.u8"), pixels);
  fs::create_directories(dir / "other");
  std::ofstream(dir / "other" / "keep.txt") << "x";
  EXPECT_THROW(write_depth_data(dir / "other", {.samples = 1}), Error);
  EXPECT_TRUE(fs::exists(dir / "other" / "keep.txt"));
  EXPECT_THROW(write_depth_data(dir / "zero", {.samples = 0}), Error);
  EXPECT_FALSE(fs::exists(dir / "zero"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pensight::sim
