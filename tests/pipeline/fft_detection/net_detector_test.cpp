#include "pipeline/fft/net_detector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/units.h"
#include "tests/support/net_image.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

TEST(NetDetector, BackendNames) {
  for (Backend b : {Backend::kAuto, Backend::kCpu, Backend::kVulkan, Backend::kCuda}) {
    EXPECT_EQ(parse_backend(to_string(b)), b);
  }
  EXPECT_THROW(parse_backend("gpu"), Error);
}

TEST(NetDetector, RejectsBadConfigurationAndImages) {
  const PinholeCamera cam;
  EXPECT_THROW(
      NetDetector(cam, {.bar_length_m = 0, .backend = Backend::kCpu}, testing::test_device()),
      Error);
  EXPECT_THROW(NetDetector(cam, {.grid = {.roi_size_px = 600}, .backend = Backend::kCpu},
                           testing::test_device()),
               Error);
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  EXPECT_THROW(detector.detect(ImageU8(640, 480)), Error);
  EXPECT_NE(NetDetector(cam, {}, testing::test_device()).backend(), Backend::kAuto);
}

// Sparse depths lie on the rendered plane, at the pixels of their ROIs.
TEST(NetDetector, SparseDepthsAreOnTheNet) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam;
  const testing::NetScene scene{
      .distance_m = 1.4, .psi_rad = 0.25, .pitch_rad = -0.1, .seed = rng()};
  NetDetector detector(cam, {.backend = Backend::kCpu, .cpu_threads = 2}, testing::test_device());
  EXPECT_NE(detector.description().find("cpu"), std::string::npos);
  const NetDetection d = detector.detect(testing::render_net(cam, scene), 1234567890123);
  ASSERT_TRUE(d.pose.valid()) << d.pose.reason;
  EXPECT_EQ(d.timestamp_ns, 1234567890123);
  EXPECT_EQ(d.lattices.size(), 30u);
  EXPECT_EQ(d.points.size(), 30u);
  // Up to 3 x 3 samples on each inlier ROI's surface.
  EXPECT_GT(static_cast<int>(d.depths.size()), 4 * d.pose.inlier_rois);
  EXPECT_LE(static_cast<int>(d.depths.size()), 9 * d.pose.inlier_rois);
  const double a = std::tan(scene.psi_rad), b = std::tan(scene.pitch_rad);
  for (const SparseDepth& s : d.depths) {
    EXPECT_TRUE(cam.in_image({s.point.x_px, s.point.y_px}));
    const Eigen::Vector3d r = cam.ray({s.point.x_px, s.point.y_px});
    const double z = scene.distance_m / (1 - a * r.x() - b * r.y());
    EXPECT_NEAR(s.point.depth_m, z, 0.03 * z) << s.point.x_px << ", " << s.point.y_px;
  }
  EXPECT_GE(d.fft_ms, 0);
  EXPECT_GE(d.pose_ms, 0);
}

// The Vulkan backend (lavapipe here) gives the CPU's pose.
// The net changes under the camera (a new panel, a diamond section, a frame of another pen): the
// opening angle the detector carries is a prior, so the first frame of each net already has a
// pose, and the right one.
TEST(NetDetector, AChangingNetRecoversOnItsFirstFrame) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> distance(0.7, 2.0), angle(-0.4, 0.4);
  const PinholeCamera cam;
  NetDetector detector(cam, {.backend = Backend::kCpu}, testing::test_device());
  struct Net {
    MeshType type;
    double opening_deg;
  };
  const Net nets[] = {{MeshType::kSquare, 104}, {MeshType::kDiamond, 72},
                      {MeshType::kSquare, 92},  {MeshType::kDiamond, 116},
                      {MeshType::kSquare, 97},  {MeshType::kDiamond, 84}};
  int frame = 0;
  for (const Net& net : nets) {
    for (int k = 0; k < 3; ++k, ++frame) {
      const testing::NetScene scene{.distance_m = distance(rng),
                                    .psi_rad = angle(rng),
                                    .pitch_rad = angle(rng) / 2,
                                    .mesh_type = net.type,
                                    .opening_angle_rad = deg_to_rad(net.opening_deg),
                                    .seed = rng()};
      const NetDetection d = detector.detect(testing::render_net(cam, scene));
      ASSERT_TRUE(d.pose.valid()) << "frame " << frame << " (" << k
                                  << " of this net): " << d.pose.reason;
      EXPECT_NEAR(d.pose.d_net_m, scene.distance_m, 0.02 * scene.distance_m) << "frame " << frame;
      EXPECT_NEAR(d.pose.psi_net_rad, scene.psi_rad, deg_to_rad(2)) << "frame " << frame;
      EXPECT_NEAR(d.mesh_angle_frame.opening_angle_rad, deg_to_rad(net.opening_deg), deg_to_rad(3))
          << "frame " << frame;
    }
  }
}

TEST(NetDetector, VulkanBackendMatchesCpu) {
  std::mt19937_64 rng(testing::fresh_seed());
  const PinholeCamera cam{.k1 = -0.03};
  const testing::NetScene scene{.distance_m = 0.9, .psi_rad = -0.3, .seed = rng()};
  const ImageU8 frame = testing::render_net(cam, scene);
  NetDetector cpu(cam, {.backend = Backend::kCpu}, testing::test_device());
  NetDetector vulkan(cam, {.backend = Backend::kVulkan}, testing::test_device());
  EXPECT_EQ(vulkan.backend(), Backend::kVulkan);
  const NetDetection c = cpu.detect(frame), v = vulkan.detect(frame);
  ASSERT_TRUE(c.pose.valid() && v.pose.valid()) << c.pose.reason << v.pose.reason;
  EXPECT_NEAR(v.pose.d_net_m, c.pose.d_net_m, 1e-4 * c.pose.d_net_m);
  EXPECT_NEAR(v.pose.psi_net_rad, c.pose.psi_net_rad, 1e-4);
  EXPECT_NEAR(v.pose.pitch_net_rad, c.pose.pitch_net_rad, 1e-4);
  EXPECT_EQ(v.pose.inlier_rois, c.pose.inlier_rois);
}

}  // namespace
}  // namespace pensight
