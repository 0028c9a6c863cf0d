#include "core/camera.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/support/test_seed.h"

namespace pensight {
namespace {

TEST(PinholeCamera, ProjectAndRayAreInverse) {
  std::mt19937_64 rng(testing::fresh_seed());
  PinholeCamera cam;
  cam.k1 = -0.21;
  cam.k2 = 0.05;
  cam.p1 = 0.001;
  cam.p2 = -0.0007;
  std::uniform_real_distribution<double> ux(-0.7, 0.7), uz(0.3, 3.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d p(ux(rng), ux(rng) * 0.75, 1.0);
    const double z = uz(rng);
    const auto px = cam.project(p * z);
    ASSERT_TRUE(px);
    const Eigen::Vector3d r = cam.ray(*px);
    EXPECT_NEAR(r.x(), p.x(), 1e-9);
    EXPECT_NEAR(r.y(), p.y(), 1e-9);
  }
  EXPECT_FALSE(cam.project({0, 0, -1}));
}

TEST(PinholeCamera, PrincipalPointAndFocalLength) {
  PinholeCamera cam;  // 720x540, fx = 462
  const auto c = cam.project({0, 0, 2});
  ASSERT_TRUE(c);
  EXPECT_DOUBLE_EQ(c->x(), 359.5);
  EXPECT_DOUBLE_EQ(c->y(), 269.5);
  const auto p = cam.project({0.1, 0, 1});
  EXPECT_DOUBLE_EQ(p->x(), 359.5 + 46.2);
}

TEST(PinholeCamera, ScaledKeepsTheImageEdges) {
  const PinholeCamera cam;
  const PinholeCamera s = cam.scaled(320.0 / 720.0);
  EXPECT_EQ(s.width_px, 320);
  EXPECT_EQ(s.height_px, 240);
  // The ray through the full image's right edge hits the scaled image's right edge.
  const Eigen::Vector3d edge = cam.ray({719.5, 269.5});
  EXPECT_NEAR(s.project(edge)->x(), 319.5, 1e-9);
}

}  // namespace
}  // namespace pensight
