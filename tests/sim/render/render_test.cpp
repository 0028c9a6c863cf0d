// The Vulkan renderer against the CPU reference: noise-free frames agree to < 1 grey level on
// average, depth to a millimetre, over near, far, oblique, bulged, tank, fish and distorted
// views; every output element is written (outputs are NaN-poisoned before each run).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "runtime/vk_buffer.h"
#include "sim/frame_state.h"
#include "sim/marine_snow.h"
#include "sim/render_cpu.h"
#include "sim/render_vk.h"
#include "tests/sim/sim_test_scenes.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::sim {
namespace {

using pensight::testing::VulkanTest;

struct Gpu {
  std::vector<float> image, depth;
};

Gpu run_vulkan(const vk::Context& ctx, const Scenario& s, const FrameState& f,
               const RenderOptions& o) {
  const RenderVk r(ctx, s, o);
  const size_t n = static_cast<size_t>(r.width()) * r.height();
  const auto data = r.frame_data(f);
  vk::Buffer frame(ctx, data.frame.size()), tiles(ctx, data.tiles.size() * sizeof(uint32_t));
  frame.upload(data.frame.data(), data.frame.size());
  tiles.upload(data.tiles.data(), data.tiles.size() * sizeof(uint32_t));
  vk::TypedBuffer<float> image(ctx, n), depth(ctx, n);
  image.fill(pensight::testing::kPoison);
  depth.fill(pensight::testing::kPoison);
  vk::CommandStream stream(ctx);
  r.record(stream, frame, tiles, image.raw(), depth.raw());
  stream.submit_and_wait();
  return {image.to_vector(), depth.to_vector()};
}

// radiance_only: both hand over the unrounded, noise-free radiance the optics work on.
void expect_match(const vk::Context& ctx, const Scenario& s, int frame = 0, bool noise = false,
                  bool radiance_only = false) {
  RenderOptions o;
  o.noise = noise;
  o.radiance_only = radiance_only;
  const NetGeometry net(s.pen, s.net);
  const FrameState f = frame_state(s, frame);
  const RenderedFrame cpu = render_cpu(s, net, f, o);
  const Gpu gpu = run_vulkan(ctx, s, f, o);
  auto cpu_pixel = [&](size_t i) {
    return radiance_only ? cpu.radiance.pixels[i] : static_cast<float>(cpu.image.pixels[i]);
  };
  ASSERT_EQ(gpu.image.size(), radiance_only ? cpu.radiance.pixels.size() : cpu.image.pixels.size());
  double sum = 0;
  size_t unwritten = 0, mask_mismatch = 0, net_pixels = 0;
  float worst_depth = 0;
  for (size_t i = 0; i < gpu.image.size(); ++i) {
    if (std::isnan(gpu.image[i]) || std::isnan(gpu.depth[i])) {
      ++unwritten;
      continue;
    }
    sum += std::abs(gpu.image[i] - cpu_pixel(i));
    const float zc = cpu.depth_m.pixels[i], zg = gpu.depth[i];
    if ((zc > 0) != (zg > 0)) {
      ++mask_mismatch;
    } else if (zc > 0) {
      ++net_pixels;
      worst_depth = std::max(worst_depth, std::abs(zc - zg));
    }
  }
  const double mean = sum / static_cast<double>(gpu.image.size());
  EXPECT_EQ(unwritten, 0u);
  EXPECT_LT(mean, 1.0) << "mean |vulkan - cpu| in grey levels";
  // Pixels whose centre ray grazes an edge (net border, fish, surface) may flip.
  EXPECT_LE(mask_mismatch, gpu.image.size() / 500);
  EXPECT_LT(worst_depth, 1e-3f);
  std::printf("  mean |vk - cpu| = %.3f grey, net pixels %zu, mask mismatches %zu, depth %.2e m\n",
              mean, net_pixels, mask_mismatch, static_cast<double>(worst_depth));
}

TEST_F(VulkanTest, RenderMatchesCpuNearAndFar) {
  expect_match(ctx(), testing::one_pose({.net_distance_m = 0.7}));
  expect_match(ctx(), testing::one_pose({.net_distance_m = 2.8, .heading_rad = 0.3}));
}

TEST_F(VulkanTest, RenderMatchesCpuObliqueWithBottomAndSurface) {
  // Looking down past the wall to the bottom, and up to the surface.
  expect_match(
      ctx(), testing::one_pose(
                 {.net_distance_m = 1.0, .heading_rad = -0.6, .pitch_rad = -0.5, .depth_m = 13.5}));
  expect_match(ctx(), testing::one_pose({.net_distance_m = 1.5, .pitch_rad = 0.6, .depth_m = 1.0}));
}

TEST_F(VulkanTest, RenderMatchesCpuTurnedAway) {
  expect_match(ctx(), testing::one_pose({.net_distance_m = 1.3, .heading_rad = 2.8}));
}

TEST_F(VulkanTest, RenderMatchesCpuWithBulgesAFoldFishSnowAndDistortion) {
  const std::string extra =
      "fish:\n  - {net_distance_m: 0.4, depth_m: 4.0, speed_mps: 0, along_m: 0.1}\n"
      "water: {marine_snow: 0.3}\n";
  Scenario s = testing::one_pose({.net_distance_m = 1.2}, 180, 135,
                                 "{shape: cylinder, radius_m: 12, depth_m: 15}", extra,
                                 ", distortion: [-0.2, 0.05, 0.001, -0.001]");
  s.net.bulges = {{0.2, 4.1, 0.3, 0.6}, {-0.5, 3.5, -0.1, 0.4}, {0.3, 4.0, -0.2, 0.6, true}};
  s.net.mesh_type = MeshType::kDiamond;
  ASSERT_GT(snow_spots(s, frame_state(s, 0)).size(), 3u);
  expect_match(ctx(), s);
}

TEST_F(VulkanTest, RenderMatchesCpuAcrossAzimuthPi) {
  // The lattice, fouling and a bulge continue across the seam of the along coordinate.
  Scenario s = testing::one_pose({.net_distance_m = 0.8, .along_m = std::numbers::pi * 12});
  s.net.bulges = {{std::numbers::pi * 12 - 0.1, 4.0, 0.1, 0.4}};
  expect_match(ctx(), s);
}

TEST_F(VulkanTest, RenderMatchesCpuShearedSquareMeshWithRoundKnots) {
  // A 27.5 mm square mesh sheared to 100 deg, heavy twine, round knots: near, where the knots
  // are sharp discs, and far, where they fade to their mean.
  for (const double distance : {0.9, 2.8}) {
    Scenario s = testing::one_pose({.net_distance_m = distance, .heading_rad = 0.2});
    s.net.bar_length_m = 0.0275;
    s.net.opening_angle_deg = 100;
    s.net.twine_width_m = 0.007;
    s.net.knot_size_m = 0.0095;
    s.net.knot_shape = KnotShape::kRound;
    expect_match(ctx(), s);
  }
}

TEST_F(VulkanTest, RenderMatchesCpuDeformedDiamondMesh) {
  // Opening angle 75 deg +-3 deg, stretch +-3 %; also across azimuth pi, where the
  // deformation fades out.
  for (const double along : {0.0, std::numbers::pi * 12 - 1.0}) {
    Scenario s = testing::one_pose({.net_distance_m = 1.0, .along_m = along});
    s.net.mesh_type = MeshType::kDiamond;
    s.net.opening_angle_deg = 75;
    s.net.opening_angle_variation_deg = 3;
    s.net.stretch_variation = 0.03;
    s.net.deform_scale_m = 1.5;
    s.net.knot_size_m = 0;
    expect_match(ctx(), s);
  }
}

TEST_F(VulkanTest, RenderMatchesCpuWithFouledPatchesRopesAndSeams) {
  // Half the net in fouled patches with clumps, ropes every 0.3 m and seams every 0.25 m (so
  // both cross the small view): on the wall near and far, and on the bottom.
  for (const testing::Pose& pose :
       {testing::Pose{.net_distance_m = 0.8}, testing::Pose{.net_distance_m = 2.5},
        testing::Pose{.net_distance_m = 1.0, .pitch_rad = -0.9, .depth_m = 13.5}}) {
    Scenario s = testing::one_pose(pose);
    s.net.fouling_coverage = 0.5;
    s.net.fouling_scale_m = 0.2;
    s.net.ropes = {.spacing_m = 0.3, .width_m = 0.02, .albedo = 0.6};
    s.net.seam_spacing_m = 0.25;
    s.net.knot_shape = KnotShape::kRound;
    expect_match(ctx(), s);
    // The features show: the frame differs from the plain net's by more than a grey level.
    const NetGeometry net(s.pen, s.net);
    const RenderOptions o{.noise = false, .marine_snow = false};
    const RenderedFrame with = render_cpu(s, net, frame_state(s, 0), o);
    Scenario plain = testing::one_pose(pose);
    const RenderedFrame without =
        render_cpu(plain, NetGeometry(plain.pen, plain.net), frame_state(plain, 0), o);
    double diff = 0;
    for (size_t i = 0; i < with.image.pixels.size(); ++i) {
      diff += std::abs(with.image.pixels[i] - without.image.pixels[i]);
    }
    EXPECT_GT(diff / static_cast<double>(with.image.pixels.size()), 1.0);
  }
}

TEST_F(VulkanTest, RenderMatchesCpuInTank) {
  expect_match(ctx(), testing::one_pose({.net_distance_m = 1.0, .heading_rad = 0.4, .depth_m = 1.0},
                                        180, 135,
                                        "{shape: plane, radius_m: 100, width_m: 4.9, top_m: 0.5, "
                                        "height_m: 1.5, wall_gap_m: 1.0}"));
}

TEST_F(VulkanTest, RenderMatchesCpuWithNoise) {
  // Both draw the same hash-based noise, so even noisy frames agree closely.
  expect_match(ctx(), testing::one_pose({.net_distance_m = 1.0}), 3, true);
}

TEST_F(VulkanTest, RenderMatchesCpuAtFullSize) {
  Scenario s = testing::one_pose({.net_distance_m = 0.9, .heading_rad = 0.2}, 720, 540);
  s.camera.samples_per_axis = 1;
  expect_match(ctx(), s);
}

// A scene moving along the net with every optics key on: defocus, motion blur, colour, JPEG.
Scenario sea_camera() {
  Scenario s = testing::one_pose({.net_distance_m = 0.8}, 180, 135,
                                 "{shape: cylinder, radius_m: 12, depth_m: 15}", "",
                                 ", focus_distance_m: 1.5, f_number: 1.4, pixel_pitch_m: 20e-6, "
                                 "exposure_time_s: 0.03, colour: true, jpeg_quality: 60");
  Waypoint w = s.waypoints[0];
  w.t_s = 2;
  w.along_m += 0.6;
  s.waypoints.push_back(w);
  s.duration_s = 2;
  validate(s);
  return s;
}

TEST_F(VulkanTest, RenderMatchesCpuRadianceForTheOptics) {
  expect_match(ctx(), sea_camera(), 5, false, true);
}

TEST_F(VulkanTest, RenderMatchesCpuThroughTheOptics) {
  // The optics run on the CPU for both, on radiance that differs by float rounding only; the
  // noise is hashed, so the frames agree except where a rounding or a JPEG block flips.
  const Scenario s = sea_camera();
  const FrameState f = frame_state(s, 5);
  const RenderedFrame cpu = render_cpu(s, NetGeometry(s.pen, s.net), f);
  RenderVk vk(ctx(), s);
  const RenderedFrame gpu = vk.render(f);
  ASSERT_EQ(gpu.image_rgb.pixels.size(), cpu.image_rgb.pixels.size());
  ASSERT_TRUE(gpu.image.empty());
  double sum = 0;
  for (size_t i = 0; i < cpu.image_rgb.pixels.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      sum += std::abs(gpu.image_rgb.pixels[i][k] - cpu.image_rgb.pixels[i][k]);
  }
  const double mean = sum / (3.0 * static_cast<double>(cpu.image_rgb.pixels.size()));
  std::printf("  through the optics: mean |vk - cpu| = %.3f grey\n", mean);
  EXPECT_LT(mean, 1.0);
}

}  // namespace
}  // namespace pensight::sim
