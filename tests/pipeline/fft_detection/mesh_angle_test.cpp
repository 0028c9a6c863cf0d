// The lattice model of net_geometry.h for cells of any opening angle, the basis reduction, and
// the frame-level opening angle of mesh_angle.h, on exact lattices of known planar nets.
#include "pipeline/fft/mesh_angle.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "core/units.h"
#include "tests/support/exact_lattice.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

constexpr double kBar = 0.030;

struct Net {
  double a, b, c;  // z = a x + b y + c in C
  MeshType type = MeshType::kSquare;
  double angle_rad = std::numbers::pi / 2;
  double rotation_rad = 0;  // the lattice in the plane
  Eigen::Vector3d normal() const { return Eigen::Vector3d(-a, -b, 1).normalized(); }
};

// The net's two bars at a point, as tests/support/net_image.h draws them: square = the net's
// right and the angle from it towards up, diamond = +-angle/2 from up.
std::array<Eigen::Vector3d, 2> bars(const Net& n) {
  const Eigen::Vector3d m = n.normal();
  const Eigen::Vector3d u1 = Eigen::Vector3d(m.z(), 0, -m.x()).normalized(), u2 = m.cross(u1);
  const double cr = std::cos(n.rotation_rad), sr = std::sin(n.rotation_rad);
  const Eigen::Vector3d right = cr * u1 + sr * u2, up = sr * u1 - cr * u2;
  const double t = n.angle_rad;
  if (n.type == MeshType::kDiamond) {
    return {kBar * (std::sin(t / 2) * right + std::cos(t / 2) * up),
            kBar * (-std::sin(t / 2) * right + std::cos(t / 2) * up)};
  }
  return {kBar * right, kBar * (std::cos(t) * right + std::sin(t) * up)};
}

// The RoiLattice the net gives at a pixel (frequencies of the two given lattice vectors, in
// units of the bars: {1, 0} and {0, 1} are the bars, {1, 1} the cell's diagonal).
kernels::RoiLattice exact_lattice(const PinholeCamera& cam, const Net& n, Eigen::Vector2d c_px,
                                  Eigen::Vector3d* p_out, Eigen::Vector2i v1 = {1, 0},
                                  Eigen::Vector2i v2 = {0, 1}) {
  const Eigen::Vector3d r = cam.ray(c_px);
  const Eigen::Vector3d p = r * (n.c / (1 - n.a * r.x() - n.b * r.y()));
  const auto b = bars(n);
  Eigen::Matrix2d a;
  const double eps = 1e-4;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2i k = i == 0 ? v1 : v2;
    const Eigen::Vector3d e = k.x() * b[0] + k.y() * b[1];
    a.col(i) = (*cam.project(p + eps * e) - *cam.project(p - eps * e)) / (2 * eps);
  }
  *p_out = p;
  return testing::lattice_of(a);
}

// The per-ROI closed form with the right opening angle recovers the range of sheared and diamond
// cells, also when the spectrum's basis holds the cell's diagonal (reduced to the bars).
TEST(MeshModel, RangeOfAnyCellAndOfADiagonalBasis) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> d(0.4, 2.5), ang(-0.5, 0.5), open(70, 115), rot(-0.2, 0.2),
      ox(0, 420), oy(0, 240);
  const PinholeCamera cam{.k1 = -0.05, .k2 = 0.01};
  int measured = 0;
  double worst_square = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Net n{std::tan(ang(rng)),
                std::tan(ang(rng) / 2),
                d(rng),
                trial % 2 ? MeshType::kDiamond : MeshType::kSquare,
                deg_to_rad(open(rng)),
                rot(rng)};
    const kernels::RoiOrigin o{static_cast<int32_t>(ox(rng)), static_cast<int32_t>(oy(rng))};
    const Eigen::Vector2d c(o.x + 149.5, o.y + 149.5);
    Eigen::Vector3d p;
    // The long diagonal (the one a knot pattern's spectrum can hold as strongly as a bar).
    const Eigen::Vector2i diagonal = trial % 3                            ? Eigen::Vector2i(0, 1)
                                     : n.angle_rad < std::numbers::pi / 2 ? Eigen::Vector2i(1, 1)
                                                                          : Eigen::Vector2i(1, -1);
    const auto lattice = exact_lattice(cam, n, c, &p, {1, 0}, diagonal);
    const Eigen::Vector3d normal = n.normal();
    const RoiNetPoint q = roi_net_point(lattice, o, 300, cam, {kBar, n.angle_rad}, {}, &normal);
    if (q.status == RoiStatus::kTooFine) continue;  // far and oblique: below the ROI's resolution
    ++measured;
    ASSERT_TRUE(q.valid()) << to_string(q.status);
    EXPECT_EQ(q.reduced, diagonal.x() == 1) << "trial " << trial;
    EXPECT_NEAR(q.range_m / p.norm(), 1.0, 2e-3) << "trial " << trial;
    const double best = std::max(q.normals_C[0].dot(normal), q.normals_C[1].dot(normal));
    EXPECT_GT(best, std::cos(0.01)) << "trial " << trial;
    // The square model reads the same cell's range off by up to 1 - 1 / sqrt(1 + |cos a|), less
    // where the tilt happens to foreshorten the cell's long diagonal.
    const RoiNetPoint square = roi_net_point(lattice, o, 300, cam, {kBar}, {}, &normal);
    worst_square = std::max(worst_square, std::abs(square.range_m / p.norm() - 1));
  }
  EXPECT_GE(measured, 45);
  EXPECT_GT(worst_square, 0.05);
}

// Net points of a whole ROI grid for one net.
std::vector<RoiNetPoint> grid(const PinholeCamera& cam, const Net& n, double model_angle_rad) {
  std::vector<RoiNetPoint> points;
  for (const kernels::RoiOrigin& o : kernels::roi_grid(720, 540, {})) {
    Eigen::Vector3d p;
    const auto l = exact_lattice(cam, n, {o.x + 149.5, o.y + 149.5}, &p);
    points.push_back(roi_net_point(l, o, 300, cam, {kBar, model_angle_rad}));
  }
  return points;
}

// The same normal for every ROI: one plane's.
std::vector<Eigen::Vector3d> same_normal(std::span<const RoiNetPoint> points,
                                         const Eigen::Vector3d& normal) {
  return std::vector<Eigen::Vector3d>(points.size(), normal);
}

TEST(MeshAngle, MeasuredAgainstThePlaneForBothMeshTypes) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> d(0.5, 2.0), ang(-0.5, 0.5), square(85, 115),
      diamond(65, 120), rot(-0.1, 0.1);
  const PinholeCamera cam;
  for (int trial = 0; trial < 20; ++trial) {
    const bool is_diamond = trial % 2;
    const Net n{std::tan(ang(rng)),
                std::tan(ang(rng) / 2),
                d(rng),
                is_diamond ? MeshType::kDiamond : MeshType::kSquare,
                deg_to_rad(is_diamond ? diamond(rng) : square(rng)),
                rot(rng)};
    const auto points = grid(cam, n, std::numbers::pi / 2);
    const std::vector<uint8_t> use(points.size(), 1);
    // The type given, and recognised from the lattice's orientation when not.
    for (const std::optional<MeshType> given :
         {std::optional<MeshType>(n.type), std::optional<MeshType>()}) {
      const MeshAngleMeasurement m =
          measure_mesh_angle(points, use, same_normal(points, n.normal()), cam, given);
      ASSERT_TRUE(m.valid()) << "trial " << trial;
      EXPECT_EQ(m.type, n.type) << "trial " << trial;
      EXPECT_NEAR(m.opening_angle_rad, n.angle_rad, deg_to_rad(0.05)) << "trial " << trial;
    }
    // The other type given (scene.yaml's net, a diamond section in view): a prior, overruled
    // where the lattice's orientation is clear (any diamond here, rotated <= 5.7 deg; a square
    // up to 105 deg).
    const MeshType other = is_diamond ? MeshType::kSquare : MeshType::kDiamond;
    const MeshAngleMeasurement m =
        measure_mesh_angle(points, use, same_normal(points, n.normal()), cam, other);
    if (is_diamond || n.angle_rad <= deg_to_rad(105)) {
      EXPECT_EQ(m.type, n.type) << "trial " << trial;
      EXPECT_NEAR(m.opening_angle_rad, n.angle_rad, deg_to_rad(0.05)) << "trial " << trial;
    }
  }
  // Too few usable ROIs: no measurement.
  const auto points = grid(cam, {0, 0, 1}, std::numbers::pi / 2);
  std::vector<uint8_t> use(points.size(), 0);
  use[0] = use[1] = use[2] = 1;
  EXPECT_FALSE(
      measure_mesh_angle(points, use, same_normal(points, {0, 0, -1}), cam, std::nullopt).valid());
}

// A 100 deg diamond on a 12 m pen wall 2.5 m ahead: each ROI's cell lies on the wall's tangent
// plane where the ROI sees it, turned up to 9 deg from the plane at the optical axis. Read against
// each ROI's own normal the angle is exact; against the one plane's it opens by half a degree
// and more (a horizontal stretch of 1 / cos of the turn at the sides).
TEST(MeshAngle, ADiamondOnACurvedWallIsReadWhereEachRoiSeesIt) {
  const double radius = 12, d = 2.5, angle = deg_to_rad(100);
  const PinholeCamera cam;
  std::vector<RoiNetPoint> points;
  std::vector<Eigen::Vector3d> normals;
  for (const kernels::RoiOrigin& o : kernels::roi_grid(720, 540, {})) {
    const Eigen::Vector2d c(o.x + 149.5, o.y + 149.5);
    const Eigen::Vector3d r = cam.ray(c);
    // Ray (t r) meets the vertical cylinder x^2 + (z + R - d)^2 = R^2; the wall's tangent plane
    // there is the ROI's net.
    const double qa = r.x() * r.x() + r.z() * r.z(), qb = 2 * r.z() * (radius - d),
                 qc = (radius - d) * (radius - d) - radius * radius;
    const Eigen::Vector3d p = r * ((-qb + std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa));
    const double slope = -p.x() / (p.z() + radius - d);
    const Net tangent{slope, 0, p.z() - slope * p.x(), MeshType::kDiamond, angle, 0};
    Eigen::Vector3d on_wall;
    const auto l = exact_lattice(cam, tangent, c, &on_wall);
    const Eigen::Vector3d normal = tangent.normal();
    points.push_back(roi_net_point(l, o, 300, cam, {kBar, angle}, {}, &normal));
    normals.push_back(normal);
  }
  const std::vector<uint8_t> use(points.size(), 1);
  const MeshAngleMeasurement local =
      measure_mesh_angle(points, use, normals, cam, MeshType::kDiamond);
  ASSERT_TRUE(local.valid());
  EXPECT_NEAR(local.opening_angle_rad, angle, deg_to_rad(0.05));
  const MeshAngleMeasurement one_plane = measure_mesh_angle(
      points, use, same_normal(points, Net{0, 0, d}.normal()), cam, MeshType::kDiamond);
  ASSERT_TRUE(one_plane.valid());
  EXPECT_GT(one_plane.opening_angle_rad - angle, deg_to_rad(0.3));
}

MeshAngleMeasurement measurement(double angle_rad, double sigma_rad) {
  return {angle_rad, sigma_rad, MeshType::kSquare, 20};
}

TEST(MeshAngle, FilterStartsFromPriorOrFirstFrameAndRestartsOnANewNet) {
  MeshAngleFilter none(std::nullopt);
  EXPECT_FALSE(none.has_estimate());
  EXPECT_DOUBLE_EQ(none.angle_rad(), std::numbers::pi / 2);
  EXPECT_NEAR(none.update(measurement(deg_to_rad(100), deg_to_rad(0.2))), deg_to_rad(100), 1e-12);
  // Noisy frames of one unchanging net average down: 2 deg frames, 30 of them, 0.37 deg; the
  // bound is 4 sigma.
  std::mt19937_64 rng(testing::fresh_seed());
  std::normal_distribution<double> noise(0, deg_to_rad(2));
  MeshAngleFilter still(std::nullopt, {.process_sigma_rad = 0});
  for (int i = 0; i < 30; ++i) {
    still.update(measurement(deg_to_rad(100) + noise(rng), deg_to_rad(2)));
  }
  EXPECT_NEAR(still.angle_rad(), deg_to_rad(100), deg_to_rad(1.5));
  // One outlier frame is held off; a net that stays different takes over after 3 frames.
  EXPECT_NEAR(none.update(measurement(deg_to_rad(80), deg_to_rad(0.2))), deg_to_rad(100), 1e-12);
  none.update(measurement(deg_to_rad(80), deg_to_rad(0.2)));
  EXPECT_NEAR(none.update(measurement(deg_to_rad(80), deg_to_rad(0.2))), deg_to_rad(80), 1e-12);
  // A prior 10 deg off is corrected by the first frame; refine replaces that frame's measurement.
  MeshAngleFilter prior(deg_to_rad(90));
  EXPECT_TRUE(prior.has_estimate());
  EXPECT_NEAR(prior.update(measurement(deg_to_rad(101), deg_to_rad(0.3))), deg_to_rad(101),
              deg_to_rad(0.1));
  EXPECT_NEAR(prior.refine(measurement(deg_to_rad(102), deg_to_rad(0.3))), deg_to_rad(102),
              deg_to_rad(0.1));
  // A frame without a measurement leaves the estimate.
  EXPECT_NEAR(prior.update({}), deg_to_rad(102), deg_to_rad(0.1));
}

}  // namespace
}  // namespace pensight
