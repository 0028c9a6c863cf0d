#include "pipeline/fft/relative_pose_fft.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/units.h"
#include "kernels/fft_roi/fft_roi.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

// Valid net points on the centre rays of the default ROI grid, on the surface depth(ray), with
// the surface normal there (both candidates, as roi_net_point gives them when the tilt is 0).
template <class Surface>
std::vector<RoiNetPoint> grid_points(Surface surface) {
  const PinholeCamera cam;
  auto at = [&](const Eigen::Vector2d& px) -> Eigen::Vector3d {
    const Eigen::Vector3d r = cam.ray(px);
    return r * surface(r);
  };
  std::vector<RoiNetPoint> pts;
  for (const auto& o : kernels::roi_grid(720, 540, {})) {
    RoiNetPoint p;
    p.status = RoiStatus::kValid;
    p.quality = 0.2;
    p.origin = o;
    p.centre_px = {o.x + 149.5, o.y + 149.5};
    p.p_C = at(p.centre_px);
    p.range_m = p.p_C.norm();
    const Eigen::Vector2d dx(5, 0), dy(0, 5);
    Eigen::Vector3d n = (at(p.centre_px + dx) - at(p.centre_px - dx))
                            .cross(at(p.centre_px + dy) - at(p.centre_px - dy))
                            .normalized();
    if (n.z() < 0) n = -n;
    p.normals_C = {n, n};
    pts.push_back(p);
  }
  return pts;
}

// The net plane of psi_net, pitch_net and d_net (z = tan(psi) x + tan(pitch) y + d in C).
struct NetPlane {
  double psi_rad, pitch_rad, d_m;
};

std::vector<RoiNetPoint> points_on(const NetPlane& p) {
  const double a = std::tan(p.psi_rad), b = std::tan(p.pitch_rad);
  return grid_points([&](const Eigen::Vector3d& r) { return p.d_m / (1 - a * r.x() - b * r.y()); });
}

// The pose is `truth`, exactly.
void expect_exact(const FftRelativePose& pose, const NetPlane& truth) {
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_NEAR(pose.d_net_m, truth.d_m, 1e-9);
  EXPECT_NEAR(pose.psi_net_rad, truth.psi_rad, 1e-9);
  EXPECT_NEAR(pose.pitch_net_rad, truth.pitch_rad, 1e-9);
}

TEST(RelativePoseFft, RecoversAnExactPlane) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> ang(-0.6, 0.6), d(0.4, 3);
  for (int trial = 0; trial < 10; ++trial) {
    const NetPlane truth{ang(rng), ang(rng) / 2, d(rng)};
    const FftRelativePose pose = relative_pose_fft(points_on(truth));
    expect_exact(pose, truth);
    EXPECT_EQ(pose.inlier_rois, 30);
    EXPECT_LT(pose.rms_residual_m, 1e-9);
  }
}

TEST(RelativePoseFft, IgnoresOutlierRois) {
  std::mt19937_64 rng(testing::fresh_seed());
  const double a = std::tan(0.3), b = std::tan(-0.1), c = 1.3;
  auto pts = grid_points([&](const Eigen::Vector3d& r) { return c / (1 - a * r.x() - b * r.y()); });
  // A third of the ROIs wrong: harmonics (half the range), a fish at 0.5 m, random.
  std::uniform_real_distribution<double> scale(0.3, 1.8);
  std::vector<int> bad = {0, 4, 7, 11, 13, 17, 20, 23, 26, 29};
  for (int i : bad) pts[i].p_C *= i % 2 ? 0.5 : scale(rng) < 1 ? 0.6 : 1.5;
  const FftRelativePose pose = relative_pose_fft(pts);
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_NEAR(pose.d_net_m, c, 1e-9);
  EXPECT_NEAR(pose.psi_net_rad, 0.3, 1e-9);
  EXPECT_NEAR(pose.pitch_net_rad, -0.1, 1e-9);
  EXPECT_EQ(pose.inlier_rois, 20);
  for (int i : bad) EXPECT_EQ(pose.inlier[i], 0) << i;
}

// Ropes, a seam and a fold cross more than half of the ROIs: their points stay near the net (a
// rope lies on it) but their lattices show another orientation. The pose comes from the ROIs that
// agree in both, exactly, and the others are named as tilted otherwise.
TEST(RelativePoseFft, APoseFromTheRoisThatAgreeWhenMostAreTiltedOtherwise) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> ang(-0.5, 0.5), d(0.5, 2.5), off(0.35, 0.7),
      along(-0.02, 0.02), axis(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const NetPlane truth{ang(rng), ang(rng) / 2, d(rng)};
    auto pts = points_on(truth);
    std::vector<int> order(pts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::shuffle(order.begin(), order.end(), rng);
    const std::vector<int> crossed(order.begin(), order.begin() + 17);
    for (int i : crossed) {
      const Eigen::Vector3d turn_axis = Eigen::Vector3d(axis(rng), axis(rng), 0).normalized();
      const Eigen::Vector3d n =
          Eigen::AngleAxisd(off(rng), turn_axis) * pts[static_cast<size_t>(i)].normals_C[0];
      pts[static_cast<size_t>(i)].normals_C = {n, n};
      pts[static_cast<size_t>(i)].p_C *= 1 + along(rng);
    }
    const FftRelativePose pose = relative_pose_fft(pts);
    expect_exact(pose, truth);
    EXPECT_EQ(pose.inlier_rois, 13);
    for (int i : crossed) {
      EXPECT_EQ(pose.inlier[static_cast<size_t>(i)], 0) << i;
      EXPECT_EQ(pose.other_tilt[static_cast<size_t>(i)], 1) << i;
    }
  }
}

// Two panels meeting in a vertical fold (a ridge towards the camera or a valley), the fold line
// between the ROI columns: the pose is the panel's the optical axis meets, whichever has more
// ROIs, and the other panel's ROIs are named.
TEST(RelativePoseFft, AFoldGivesThePoseOfThePanelOnTheAxis) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> ang(-0.3, 0.3), kink(0.2, 0.5), d(0.6, 2.5),
      near_axis(-0.08, 0.08), beside(0.1, 0.26);
  for (int trial = 0; trial < 40; ++trial) {
    const bool valley = trial % 2 == 0;
    // The fold line at normalised x = xf; the panel P on the axis side, Q beyond.
    const double xf = (trial / 2) % 2 == 0 ? near_axis(rng) : beside(rng) * (ang(rng) > 0 ? 1 : -1);
    const double psi_p = ang(rng), d_p = d(rng);
    // Beyond a valley's fold (pointing away from the camera) Q comes nearer than P would be;
    // beyond a ridge's (pointing at it) it falls away.
    const double side = xf > 0 ? 1 : -1;
    const double psi_q = psi_p + (valley ? -1 : 1) * side * kink(rng);
    const double tp = std::tan(psi_p), tq = std::tan(psi_q);
    // Both planes through the fold line's point at depth z_f on the ray xf: z = d + t X.
    const double z_f = d_p / (1 - tp * xf), d_q = z_f - tq * xf * z_f;
    auto pts = grid_points([&](const Eigen::Vector3d& r) {
      const double zp = d_p / (1 - tp * r.x()), zq = d_q / (1 - tq * r.x());
      return (r.x() - xf) * side < 0 ? zp : zq;
    });
    const FftRelativePose pose = relative_pose_fft(pts);
    ASSERT_TRUE(pose.valid()) << trial << ": " << pose.reason;
    EXPECT_NEAR(pose.d_net_m, d_p, 1e-3 * d_p) << trial;
    EXPECT_NEAR(pose.psi_net_rad, psi_p, 2e-3) << trial;
    int second = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      const double x = pts[i].p_C.x() / pts[i].p_C.z();
      const bool on_q = (x - xf) * side > 0;
      if (on_q) second += pose.second_panel[i];
      EXPECT_EQ(pose.inlier[i], on_q ? 0 : 1) << trial << " ROI " << i;
    }
    EXPECT_GT(second, 0) << trial;
  }
}

// Net points on a vertical cylinder of `radius` seen from inside, d_m ahead on the optical axis.
std::vector<RoiNetPoint> points_on_wall(double radius, double d_m) {
  return grid_points([&](const Eigen::Vector3d& r) {
    // Ray (t r) meets the vertical cylinder x^2 + (z + R - d)^2 = R^2.
    const double qa = r.x() * r.x() + 1, qb = 2 * (radius - d_m),
                 qc = (radius - d_m) * (radius - d_m) - radius * radius;
    return (-qb + std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
  });
}

// A pen wall of radius 12 m seen from inside bends towards the camera at the sides; the
// paraboloid keeps d_net on the optical axis where a plane would put it too close.
TEST(RelativePoseFft, ParaboloidFollowsACurvedWall) {
  const double d = 2.5;
  const auto pts = points_on_wall(12, d);
  const FftRelativePose pose = relative_pose_fft(pts);
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_NEAR(pose.d_net_m, d, 0.005 * d);
  EXPECT_NEAR(pose.psi_net_rad, 0.0, 1e-6);
}

// The same wall 6.5 m away: its normal turns by +-17 deg across the view and the ROIs' own tilts
// follow it. They agree with the wall the paraboloid measures (a pose), not with a flat panel's
// (none); a surface that curves 4x more than the wall (a 3 m bulge) does not vouch for its ROIs'
// tilts.
TEST(RelativePoseFft, RoiTiltsAgreeWithTheWallTheyAreOn) {
  RelativePoseFftParams params;
  params.wall_curvature_per_m = 1 / 12.0;
  const auto far_wall = points_on_wall(12, 6.5);
  const FftRelativePose pose = relative_pose_fft(far_wall, params);
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_NEAR(pose.d_net_m, 6.5, 0.005 * 6.5);
  EXPECT_NEAR(pose.psi_net_rad, 0.0, 1e-6);
  params.wall_curvature_per_m = 0;
  const FftRelativePose flat = relative_pose_fft(far_wall, params);
  EXPECT_FALSE(flat.valid());
  EXPECT_NE(flat.reason.find("tilts disagree"), std::string::npos) << flat.reason;

  params.wall_curvature_per_m = 1 / 12.0;
  const auto bulge = points_on_wall(3, 2.5);
  EXPECT_FALSE(relative_pose_fft(bulge, params).valid());
  params.wall_curvature_per_m = 1 / 3.0;
  const FftRelativePose on_bulge = relative_pose_fft(bulge, params);
  ASSERT_TRUE(on_bulge.valid()) << on_bulge.reason;
  EXPECT_NEAR(on_bulge.d_net_m, 2.5, 0.005 * 2.5);
}

// The wall 2.5 m away with its top and bottom ROI rows read 1.5 % far (fouling's bias on rows
// that span little height): the paraboloid through all rows curves in y beyond the wall, yet the
// net's normals at the ROIs keep the wall's curve across the view (the x^2 term alone), where
// the plane's would be 5 deg off at the sides and read a diamond's opening angle open.
TEST(RelativePoseFft, TheWallsCurveAcrossTheViewOutlivesACurveTheRowsCannotTell) {
  const double radius = 12, d = 2.5;
  std::vector<RoiNetPoint> pts = points_on_wall(radius, d);
  const int32_t top = pts.front().origin.y, bottom = pts.back().origin.y;
  for (RoiNetPoint& p : pts) {
    if (p.origin.y == top || p.origin.y == bottom) p.p_C *= 1.015;
  }
  const FftRelativePose pose = relative_pose_fft(pts);
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_NEAR(pose.surface_C(3), -1 / (2 * radius), 0.2 / (2 * radius));
  EXPECT_EQ(pose.surface_C(5), 0);
  for (const RoiNetPoint& p : pts) {
    // The wall's normal where the ROI sees it: towards the cylinder's axis, level.
    const Eigen::Vector3d axis_C(0, 0, d - radius);
    const Eigen::Vector3d wall_normal =
        Eigen::Vector3d(axis_C.x() - p.p_C.x(), 0, axis_C.z() - p.p_C.z()).normalized();
    const double off_rad =
        std::acos(std::min(1.0, net_surface_normal(pose.surface_C, p.p_C).dot(wall_normal)));
    EXPECT_LT(rad_to_deg(off_rad), 0.5) << "ROI at x " << p.p_C.x() << " m";
  }
}

// The net seen in three ROI columns whose ranges read +1.5, -1.5, +1.5 % (a column's bias, as on
// steep frames): an x^2 term would pass through the three columns' means and, 1-2 columns away,
// put d_net several per cent off on the optical axis; without it d_net stays within the bias.
TEST(RelativePoseFft, ThreeColumnsFitNoCurvatureAcrossThem) {
  const NetPlane truth{0.3, 0.0, 1.5};
  std::vector<RoiNetPoint> pts = points_on(truth);
  const double bias[] = {0.015, -0.015, 0.015};
  for (size_t i = 0; i < pts.size(); ++i) {
    const size_t column = i % 6;
    if (column < 3) {
      pts[i].status = RoiStatus::kPartial;
    } else {
      pts[i].p_C *= 1 + bias[column - 3];
    }
  }
  const FftRelativePose pose = relative_pose_fft(pts);
  ASSERT_TRUE(pose.valid()) << pose.reason;
  EXPECT_EQ(pose.inlier_rois, 15);
  EXPECT_NEAR(pose.d_net_m, truth.d_m, 0.015 * truth.d_m);
}

// Half the image on the net (two ROI columns): 0.7 % range noise on a 84 px baseline leaves the
// plane's psi degrees off; the per-ROI tilts (here 0.01 slope noise) bring it closer.
TEST(RelativePoseFft, RoiTiltsHelpAShortBaseline) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::normal_distribution<double> range_noise(0, 0.007), slope_noise(0, 0.01);
  const double a = std::tan(0.25), b = std::tan(0.05), c = 1.2;
  double err_plane = 0, err_fused = 0;
  for (int trial = 0; trial < 20; ++trial) {
    auto pts =
        grid_points([&](const Eigen::Vector3d& r) { return c / (1 - a * r.x() - b * r.y()); });
    for (size_t i = 0; i < pts.size(); ++i) {
      RoiNetPoint& p = pts[i];
      if (i % 6 > 1) p.status = RoiStatus::kPartial;
      p.p_C *= 1 + range_noise(rng);
      Eigen::Vector3d n = p.normals_C[0];
      n.x() += slope_noise(rng) * n.z();
      n.y() += slope_noise(rng) * n.z();
      p.normals_C = {n.normalized(), n.normalized()};
    }
    const FftRelativePose fused = relative_pose_fft(pts);
    const FftRelativePose plane = relative_pose_fft(pts, {.fuse_roi_tilt = false});
    ASSERT_TRUE(fused.valid() && plane.valid()) << fused.reason << plane.reason;
    EXPECT_EQ(fused.inlier_rois, 10);
    err_plane += std::abs(plane.psi_net_rad - 0.25) / 20;
    err_fused += std::abs(fused.psi_net_rad - 0.25) / 20;
  }
  std::printf("mean psi error: plane %.2f deg, fused %.2f deg\n", rad_to_deg(err_plane),
              rad_to_deg(err_fused));
  EXPECT_LT(err_fused, 0.7 * err_plane);
}

// Only the two left ROI columns on the net: a 20 deg plane is extrapolated to the optical axis
// with lever 0.31, a 60 deg plane with lever 1.09 (a 10 deg slope error there is 19 % of d_net).
TEST(RelativePoseFft, SteepPlaneFarFromTheAxisGivesNan) {
  for (const double psi : {0.35, 1.05}) {
    const double a = std::tan(psi), c = 1.0;
    auto pts = grid_points([&](const Eigen::Vector3d& r) { return c / (1 - a * r.x()); });
    for (size_t i = 0; i < pts.size(); ++i) {
      if (i % 6 > 1) pts[i].status = RoiStatus::kNoLattice;
    }
    const FftRelativePose pose = relative_pose_fft(pts, {.max_obliquity_rad = 1.2});
    if (psi < 0.5) {
      ASSERT_TRUE(pose.valid()) << pose.reason;
      EXPECT_NEAR(pose.d_net_m, c, 1e-9);
    } else {
      EXPECT_FALSE(pose.valid());
      EXPECT_TRUE(std::isnan(pose.d_net_m));
      EXPECT_NE(pose.reason.find("extrapolated"), std::string::npos) << pose.reason;
    }
  }
}

// Points on one plane whose ROIs all report tilts 15 deg off it (a harmonic read as the lattice
// in every ROI) give NaN; 4 deg off (per-ROI noise) is kept.
TEST(RelativePoseFft, RoiTiltsDisagreeingWithThePlaneGiveNan) {
  const double a = std::tan(0.3), c = 1.1;
  for (const double off_deg : {4.0, 15.0}) {
    auto pts = grid_points([&](const Eigen::Vector3d& r) { return c / (1 - a * r.x()); });
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(deg_to_rad(off_deg), Eigen::Vector3d::UnitY()).toRotationMatrix();
    for (RoiNetPoint& p : pts) p.normals_C = {turn * p.normals_C[0], turn * p.normals_C[1]};
    const FftRelativePose pose = relative_pose_fft(pts);
    if (off_deg < 8) {
      ASSERT_TRUE(pose.valid()) << pose.reason;
      EXPECT_NEAR(pose.d_net_m, c, 1e-9);
    } else {
      EXPECT_FALSE(pose.valid());
      EXPECT_NE(pose.reason.find("tilts disagree"), std::string::npos) << pose.reason;
    }
  }
}

TEST(RelativePoseFft, TooFewValidRoisGiveNanAndAReason) {
  auto pts = grid_points([](const Eigen::Vector3d&) { return 1.0; });
  for (size_t i = 5; i < pts.size(); ++i) pts[i].status = RoiStatus::kNoLattice;
  const FftRelativePose pose = relative_pose_fft(pts);
  EXPECT_FALSE(pose.valid());
  EXPECT_TRUE(std::isnan(pose.d_net_m) && std::isnan(pose.psi_net_rad) &&
              std::isnan(pose.pitch_net_rad));
  EXPECT_EQ(pose.valid_rois, 5);
  EXPECT_NE(pose.reason.find("only 5 of 30"), std::string::npos) << pose.reason;
  EXPECT_FALSE(relative_pose_fft({}).valid());
}

// The quality is the product of the support, the agreeing share and each check's margin: near 1
// for a whole frontal net, lowered by exactly the share of ROIs left out, by the ROIs missing
// below full support and by the obliquity; 0 without a pose.
TEST(RelativePoseFft, QualityFallsWithEachWayThePoseIsWeaker) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> d(0.5, 2.5), small(-0.05, 0.05);
  const NetPlane frontal{small(rng), small(rng), d(rng)};
  const FftRelativePose whole = relative_pose_fft(points_on(frontal));
  ASSERT_TRUE(whole.valid()) << whole.reason;
  EXPECT_GT(whole.quality, 0.8);  // the lever of the ROIs nearest the axis: 0.11 of 0.7
  EXPECT_LE(whole.quality, 1.0);

  auto outliers = points_on(frontal);  // 10 of 30 at half the range: a lattice harmonic
  for (int i : {0, 4, 7, 11, 13, 17, 20, 23, 26, 29}) outliers[static_cast<size_t>(i)].p_C *= 0.5;
  const FftRelativePose agreeing = relative_pose_fft(outliers);
  ASSERT_EQ(agreeing.inlier_rois, 20);
  EXPECT_NEAR(agreeing.quality, whole.quality * 20 / 30, 1e-6);

  auto few = points_on(frontal);  // the net in 8 ROIs about the image centre
  for (size_t i = 0; i < few.size(); ++i) {
    const size_t row = i / 6, col = i % 6;
    if (row < 1 || row > 2 || col < 1 || col > 4) few[i].status = RoiStatus::kNoLattice;
  }
  const FftRelativePose partial = relative_pose_fft(few);
  ASSERT_EQ(partial.inlier_rois, 8);
  EXPECT_LT(partial.quality, whole.quality * 8 / 12 + 0.05);

  const NetPlane oblique{0.8, 0, frontal.d_m};  // 46 deg: margin 1 - 0.8 / 0.995 = 0.2
  const FftRelativePose steep = relative_pose_fft(points_on(oblique));
  ASSERT_TRUE(steep.valid()) << steep.reason;
  EXPECT_LT(steep.quality, 0.21);
  EXPECT_GT(steep.quality, 0.05);

  auto none = points_on(frontal);
  for (size_t i = 5; i < none.size(); ++i) none[i].status = RoiStatus::kNoLattice;
  EXPECT_EQ(relative_pose_fft(none).quality, 0);
}

// Scattered points with no common plane (e.g. fish, bubbles): no consistent subset. By chance
// 12 of 30 random depths can lie on a plane (3 draws in 2000 gave a pose), so 100 draws are
// made and at most 5 may give one (p < 1e-7 at that rate).
TEST(RelativePoseFft, InconsistentPointsGiveNan) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> depth(0.3, 6);
  int with_pose = 0;
  for (int draw = 0; draw < 100; ++draw) {
    const auto pts = grid_points([&](const Eigen::Vector3d&) { return depth(rng); });
    const FftRelativePose pose = relative_pose_fft(pts, {.min_valid_rois = 12});
    if (pose.valid()) {
      ++with_pose;
    } else {
      EXPECT_FALSE(pose.reason.empty());
    }
  }
  EXPECT_LE(with_pose, 5);
}

}  // namespace
}  // namespace pensight
