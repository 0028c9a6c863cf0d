// Priors on each inlier ROI's local surface: on a plane they lie exactly on it, per_axis^2 per ROI
// inside the image, none from outliers or a NaN pose, and bad parameters are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "pipeline/fft/depth_priors.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

struct PlaneScene {
  double c_m, a, b;  // z = c + a x + b y in C
  double depth_along(const Eigen::Vector3d& ray) const {
    return c_m / (1 - a * ray.x() - b * ray.y());
  }
};

std::vector<RoiNetPoint> rois_on(const PlaneScene& plane, const PinholeCamera& cam) {
  std::vector<RoiNetPoint> rois;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 6; ++c) {
      RoiNetPoint p;
      p.status = RoiStatus::kValid;
      p.centre_px = {150 + 84 * c, 150 + 60 * r};
      const Eigen::Vector3d ray = cam.ray(p.centre_px);
      p.p_C = ray * plane.depth_along(ray);
      p.quality = 0.1 + 0.01 * (r * 6 + c);
      rois.push_back(p);
    }
  }
  return rois;
}

FftRelativePose pose_of(const PlaneScene& plane, size_t n) {
  FftRelativePose pose;
  pose.status = FftPoseStatus::kValid;
  pose.psi_net_rad = std::atan(plane.a);
  pose.pitch_net_rad = std::atan(plane.b);
  pose.d_net_m = plane.c_m;
  pose.inlier.assign(n, 1);
  return pose;
}

TEST(DepthPriors, LieOnThePlaneWithTheRoiQuality) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<> u(-0.6, 0.6);
  const PinholeCamera cam{.k1 = -0.05};
  for (int trial = 0; trial < 20; ++trial) {
    const PlaneScene plane{0.5 + std::abs(3 * u(rng)), u(rng), 0.5 * u(rng)};
    const auto rois = rois_on(plane, cam);
    FftRelativePose pose = pose_of(plane, rois.size());
    pose.inlier[7] = 0;  // an outlier ROI contributes nothing
    const std::vector<SparseDepth> priors = roi_surface_priors(rois, pose, 300, cam);
    EXPECT_GT(priors.size(), 29u * 6);
    EXPECT_LE(priors.size(), 29u * 9);
    for (const SparseDepth& s : priors) {
      const Eigen::Vector2d px(s.point.x_px, s.point.y_px);
      ASSERT_TRUE(cam.in_image(px));
      EXPECT_NEAR(s.point.depth_m, plane.depth_along(cam.ray(px)), 1e-5 * plane.c_m);
      EXPECT_NE(s.quality, rois[7].quality);
    }
  }
}

TEST(DepthPriors, OnePerRoiIsItsPoint) {
  const PinholeCamera cam;
  const PlaneScene plane{1.2, 0.3, -0.1};
  const auto rois = rois_on(plane, cam);
  const auto priors =
      roi_surface_priors(rois, pose_of(plane, rois.size()), 300, cam, {.per_axis = 1});
  ASSERT_EQ(priors.size(), rois.size());
  for (size_t i = 0; i < rois.size(); ++i) {
    EXPECT_FLOAT_EQ(priors[i].point.x_px, static_cast<float>(rois[i].centre_px.x()));
    EXPECT_NEAR(priors[i].point.depth_m, rois[i].p_C.z(), 1e-6);
    EXPECT_FLOAT_EQ(priors[i].quality, static_cast<float>(rois[i].quality));
  }
}

TEST(DepthPriors, NaNPoseGivesNoneAndBadParametersThrow) {
  const PinholeCamera cam;
  const PlaneScene plane{1, 0, 0};
  const auto rois = rois_on(plane, cam);
  FftRelativePose nan_pose;
  EXPECT_TRUE(roi_surface_priors(rois, nan_pose, 300, cam).empty());
  const FftRelativePose pose = pose_of(plane, rois.size());
  EXPECT_THROW(roi_surface_priors(rois, pose, 300, cam, {.per_axis = 0}), Error);
  EXPECT_THROW(roi_surface_priors(rois, pose, 300, cam, {.spacing_share = 0.7}), Error);
  EXPECT_THROW(roi_surface_priors(std::span(rois).first(3), pose, 300, cam), Error);
}

}  // namespace
}  // namespace pensight
