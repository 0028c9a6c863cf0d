#include "pipeline/global_pose/dvl_plane.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "tests/pipeline/global_pose/pen_sim.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::global_pose {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Ranges of the beams to the plane n.p = d (body frame).
std::array<double, 4> ranges_to_plane(const DvlCalibration& dvl, const Eigen::Vector3d& n,
                                      double d) {
  std::array<double, 4> r{};
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d o = dvl.T_body_dvl.translation();
    const Eigen::Vector3d u = dvl.T_body_dvl.linear() * dvl.beam_directions_S[i].normalized();
    r[i] = (d - n.dot(o)) / n.dot(u);
  }
  return r;
}

TEST(DvlPlane, FlatWallIsExactAndMatchesTheCameraView) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> ang(-20 * kDeg, 20 * kDeg), dist(0.8, 3.0);
  const DvlCalibration dvl = sim::forward_dvl();
  const Eigen::Isometry3d T_bc = sim::forward_camera();
  for (int trial = 0; trial < 50; ++trial) {
    const double yaw = ang(rng), tilt = ang(rng), d = dist(rng);
    // Wall normal: body +x turned by -yaw about z (so the heading is +yaw) and tilted.
    const Eigen::Vector3d n =
        (Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitX());
    const DvlPlane plane = dvl_net_plane(dvl, ranges_to_plane(dvl, n, d));
    ASSERT_TRUE(plane.ok);
    EXPECT_EQ(plane.beams, 4);
    EXPECT_NEAR(plane.distance_m, d, 1e-9);
    EXPECT_NEAR((plane.normal_B - n).norm(), 0.0, 1e-9);
    EXPECT_NEAR(plane.heading_rad, yaw, 1e-9);
    EXPECT_LT(plane.residual_rms_m, 1e-7);
    // The same wall seen by the camera: d_net along the optical axis, psi_net, pitch_net.
    const Eigen::Vector3d axis_B = T_bc.linear().col(2);
    const double d_net = (d - n.dot(T_bc.translation())) / n.dot(axis_B);
    const Eigen::Vector3d m = T_bc.linear().transpose() * n;
    const NetRelativePose rel = plane.in_camera(T_bc);
    EXPECT_NEAR(rel.d_net_m, d_net, 1e-9);
    EXPECT_NEAR(rel.psi_net_rad, std::atan2(-m.x(), m.z()), 1e-9);
    EXPECT_NEAR(rel.pitch_net_rad, std::atan2(-m.y(), m.z()), 1e-9);
    // Three beams still define the plane.
    auto three = ranges_to_plane(dvl, n, d);
    three[static_cast<size_t>(trial % 4)] = kNaN;
    const DvlPlane p3 = dvl_net_plane(dvl, three);
    ASSERT_TRUE(p3.ok);
    EXPECT_NEAR(p3.distance_m, d, 1e-9);
  }
}

TEST(DvlPlane, FewerThanThreeBeamsGiveNaN) {
  const DvlCalibration dvl = sim::forward_dvl();
  const DvlPlane plane = dvl_net_plane(dvl, {1.0, kNaN, -1.0, 2.0});
  EXPECT_FALSE(plane.ok);
  EXPECT_EQ(plane.beams, 2);
  EXPECT_TRUE(std::isnan(plane.distance_m));
  EXPECT_TRUE(std::isnan(plane.heading_rad));
  EXPECT_TRUE(std::isnan(plane.in_camera(sim::forward_camera()).d_net_m));
}

// In the pen the plane is a chord of the curved wall. Facing the wall squarely it lies within the
// sagitta of the wall; turned, its heading follows psi_r (offset by the footprint's bearing on the
// curve) and 2 cm range noise moves it by about the range noise.
TEST(DvlPlane, InThePenTracksTheRelativePose) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::normal_distribution<double> noise(0.0, 0.02);
  const DvlCalibration dvl = sim::forward_dvl();
  for (const double radius : {12.0, 25.0, 100.0}) {
    std::vector<double> heading_err, dist_err;
    std::uniform_real_distribution<double> d(0.5, 2.0), yaw(-15 * kDeg, 15 * kDeg);
    for (int i = 0; i < 200; ++i) {
      sim::Pose pose;
      const double r = radius - d(rng);
      pose.p_pen = Eigen::Vector3d(r, 0, 4);
      const DvlPlane square =
          dvl_net_plane(dvl, dvl_ranges_to_wall(dvl, pose.T_pen_body(), NetWall::cylinder(radius)));
      ASSERT_TRUE(square.ok);
      EXPECT_NEAR(square.distance_m, radius - r, 0.01);
      EXPECT_NEAR(square.heading_rad, 0.0, 1e-9);
      pose.yaw_rad = yaw(rng);
      const auto exact = dvl_ranges_to_wall(dvl, pose.T_pen_body(), NetWall::cylinder(radius));
      auto ranges = exact;
      for (auto& x : ranges) x += noise(rng);
      const DvlPlane plane = dvl_net_plane(dvl, ranges);
      ASSERT_TRUE(plane.ok);
      heading_err.push_back(std::abs(plane.heading_rad - pose.psi_r_rad()));
      dist_err.push_back(std::abs(plane.distance_m - dvl_net_plane(dvl, exact).distance_m));
    }
    const double h = sim::median(heading_err) / kDeg, dm = sim::median(dist_err);
    std::printf(
        "DVL plane R = %5.1f: heading error median %.2f deg p95 %.2f deg, distance %.3f m\n",
        radius, h, sim::percentile(heading_err, 0.95) / kDeg, dm);
    EXPECT_LE(h, 3.0);
    EXPECT_LE(dm, 0.02);
  }
}

}  // namespace
}  // namespace pensight::global_pose
