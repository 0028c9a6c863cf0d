// The FFT stage on a real frame of a full-scale salmon pen (../shared/real/solaqua_close: sheared,
// fouled, soft square mesh). There is no ground truth: the checks are that a pose comes out, that
// it is physically plausible for the stated intrinsics, and that the lattice model explains the
// frame (opening angle, ROIs whose spectrum chose a cell diagonal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/median.h"
#include "core/net_angles.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/depth/depth_input.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {

const std::filesystem::path kFrameDir =
    std::filesystem::path(PENSIGHT_SHARED_DIR) / "real" / "solaqua_close";

NetDetectorConfig config_for(const Dataset& d, Backend backend) {
  return detector_config(d.scene, {.backend = backend});
}

// Every dataset folder in ../shared/real/ (frames are added there; each must give a pose).
std::vector<std::filesystem::path> real_datasets() {
  std::vector<std::filesystem::path> out;
  const auto root = std::filesystem::path(PENSIGHT_SHARED_DIR) / "real";
  for (const auto& e : std::filesystem::directory_iterator(root)) {
    if (std::filesystem::exists(e.path() / "scene.yaml")) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Real frames have no ground truth: the pose must agree with the ROIs it came from. Its distance
// lies within the spread of the inlier ROIs' own depths on their rays, its heading and pitch within
// 5 deg of the median of the inliers' own tilts (each ROI's normal candidate nearer the pose's).
TEST(RealFrame, EveryRealFrameGivesAPoseTheAgreeingRoisSupport) {
  const auto datasets = real_datasets();
  ASSERT_GE(datasets.size(), 2u) << "../shared/real/ holds solaqua_close and solaqua_far";
  for (const auto& dir : datasets) {
    const Dataset d = read_dataset(dir);
    NetDetector detector(d.cam0.camera, config_for(d, Backend::kCpu), testing::test_device());
    for (size_t f = 0; f < d.frames.size(); ++f) {
      const NetDetection det = detector.detect(d.load_frame(f));
      const std::string where = dir.filename().string() + " frame " + std::to_string(f);
      ASSERT_TRUE(det.pose.valid()) << where << ": " << det.pose.reason;
      const Eigen::Vector3d m =
          -Eigen::Vector3d(std::tan(det.pose.psi_net_rad), std::tan(det.pose.pitch_net_rad), -1)
               .normalized();
      std::vector<double> depths, psi, pitch;
      for (size_t i = 0; i < det.points.size(); ++i) {
        if (!det.pose.inlier[i]) continue;
        const RoiNetPoint& p = det.points[i];
        depths.push_back(p.p_C.z());
        const auto& n = p.normals_C;
        const Eigen::Vector3d own = std::abs(n[0].dot(m)) >= std::abs(n[1].dot(m)) ? n[0] : n[1];
        const NetAngles a = net_angles_from_normal_C(own);
        psi.push_back(a.psi_rad);
        pitch.push_back(a.pitch_rad);
      }
      std::printf(
          "%s: d_net %.3f m (ROIs %.3f-%.3f), psi %.1f deg (ROIs' median %.1f), pitch %.1f "
          "(%.1f), %d of %d ROIs agree\n",
          where.c_str(), det.pose.d_net_m, *std::min_element(depths.begin(), depths.end()),
          *std::max_element(depths.begin(), depths.end()), rad_to_deg(det.pose.psi_net_rad),
          rad_to_deg(median(psi)), rad_to_deg(det.pose.pitch_net_rad), rad_to_deg(median(pitch)),
          det.pose.inlier_rois, det.pose.valid_rois);
      EXPECT_GE(det.pose.d_net_m, *std::min_element(depths.begin(), depths.end())) << where;
      EXPECT_LE(det.pose.d_net_m, *std::max_element(depths.begin(), depths.end())) << where;
      EXPECT_NEAR(det.pose.psi_net_rad, median(psi), deg_to_rad(5)) << where;
      EXPECT_NEAR(det.pose.pitch_net_rad, median(pitch), deg_to_rad(5)) << where;
    }
  }
}

TEST(RealFrame, SolaquaCloseGivesAPlausiblePose) {
  ASSERT_TRUE(std::filesystem::exists(kFrameDir / "scene.yaml"))
      << kFrameDir << " is missing: the project expects ../shared/ beside its checkout";
  const Dataset d = read_dataset(kFrameDir);
  const ImageU8 image = d.load_frame(0);
  // 300 px ROIs, where 8 of the frame's spectra hold the cell's diagonal (fewer do in the 438 px
  // ROIs planned for this camera): the reduction is what this test is about.
  NetDetectorConfig config = config_for(d, Backend::kCpu);
  config.grid.roi_size_px = 300;
  NetDetector detector(d.cam0.camera, config, testing::test_device());
  const NetDetection det = detector.detect(image);
  ASSERT_TRUE(det.pose.valid()) << det.pose.reason;
  std::printf(
      "d_net %.3f m, psi %.2f deg, pitch %.2f deg, opening angle %.2f deg (%s), %d of %d "
      "ROIs inliers, %d reduced\n",
      det.pose.d_net_m, rad_to_deg(det.pose.psi_net_rad), rad_to_deg(det.pose.pitch_net_rad),
      rad_to_deg(det.mesh_angle_rad), to_string(det.mesh_type), det.pose.inlier_rois,
      det.pose.valid_rois, det.reduced_rois);
  EXPECT_GE(det.pose.d_net_m, 0.15);
  EXPECT_LE(det.pose.d_net_m, 0.8);
  EXPECT_LT(std::abs(det.pose.psi_net_rad), deg_to_rad(40));
  EXPECT_GE(det.mesh_angle_rad, deg_to_rad(90));
  EXPECT_LE(det.mesh_angle_rad, deg_to_rad(115));
  EXPECT_EQ(det.mesh_type, MeshType::kSquare);
  EXPECT_GE(det.pose.inlier_rois, 20);

  // Every ROI whose basis held a diagonal, once reduced, ranges within 10 % of its grid
  // neighbours' median (unreduced, such a ROI read about 25 % short).
  const auto& rois = detector.rois();
  int checked = 0;
  for (size_t i = 0; i < det.points.size(); ++i) {
    const RoiNetPoint& p = det.points[i];
    if (!p.reduced || !det.pose.inlier[i]) continue;
    std::vector<double> around;
    for (size_t j = 0; j < det.points.size(); ++j) {
      const int dx = std::abs(rois[j].x - rois[i].x), dy = std::abs(rois[j].y - rois[i].y);
      if (j != i && det.pose.inlier[j] && dx <= 300 && dy <= 300) {
        around.push_back(det.points[j].range_m);
      }
    }
    if (around.size() < 2) continue;
    ++checked;
    EXPECT_NEAR(p.range_m / median(around), 1.0, 0.10) << "ROI " << i;
  }
  EXPECT_GE(checked, 3) << "the frame holds ROIs whose spectrum chose a diagonal";

  // The same frame on the Vulkan path: the same lattice model, the same pose.
  config.backend = Backend::kVulkan;
  NetDetector vulkan(d.cam0.camera, config, testing::test_device());
  const NetDetection v = vulkan.detect(image);
  ASSERT_TRUE(v.pose.valid()) << v.pose.reason;
  EXPECT_NEAR(v.pose.d_net_m, det.pose.d_net_m, 0.005 * det.pose.d_net_m);
  EXPECT_NEAR(v.pose.psi_net_rad, det.pose.psi_net_rad, deg_to_rad(0.2));
  EXPECT_NEAR(v.mesh_angle_rad, det.mesh_angle_rad, deg_to_rad(0.2));
}

// Issue 45: the same real frame from another camera. Resized to 1/2, 1/4 and 1.5x (resize_area,
// OpenCV's INTER_AREA) with the intrinsics scaled alike, each frame gives the pose of the original
// within 2 % and 1 deg: the planned ROIs (grid_plan.h) hold the same cells at every size.
TEST(RealFrame, TheSamePoseAtHalfAQuarterAndOneAndAHalfTheSize) {
  for (const auto& dir : real_datasets()) {
    const Dataset d = read_dataset(dir);
    const ImageU8 image = d.load_frame(0);
    NetDetector original(d.cam0.camera, config_for(d, Backend::kCpu), testing::test_device());
    const NetDetection want = original.detect(image);
    ASSERT_TRUE(want.pose.valid()) << dir << ": " << want.pose.reason;
    for (const double scale : {0.5, 0.25, 1.5}) {
      const std::string where = dir.filename().string() + " x" + std::to_string(scale);
      const PinholeCamera camera = d.cam0.camera.scaled(scale);
      const ImageU8 resized = resize_area(image, camera.width_px, camera.height_px);
      NetDetector detector(camera, config_for(d, Backend::kCpu), testing::test_device());
      const NetDetection got = detector.detect(resized);
      ASSERT_TRUE(got.pose.valid()) << where << ": " << got.pose.reason;
      std::printf(
          "%s: ROI %d px, d_net %.4f m (original %.4f), psi %.2f deg (%.2f), pitch %.2f "
          "deg (%.2f)\n",
          where.c_str(), detector.config().grid.roi_size_px, got.pose.d_net_m, want.pose.d_net_m,
          rad_to_deg(got.pose.psi_net_rad), rad_to_deg(want.pose.psi_net_rad),
          rad_to_deg(got.pose.pitch_net_rad), rad_to_deg(want.pose.pitch_net_rad));
      EXPECT_NEAR(got.pose.d_net_m, want.pose.d_net_m, 0.02 * want.pose.d_net_m) << where;
      EXPECT_NEAR(got.pose.psi_net_rad, want.pose.psi_net_rad, deg_to_rad(1)) << where;
      EXPECT_NEAR(got.pose.pitch_net_rad, want.pose.pitch_net_rad, deg_to_rad(1)) << where;
    }
  }
}

}  // namespace
}  // namespace pensight
