// The net lattice closes around the cylinder: the twine pattern, the fouling and the bulges
// continue across the azimuth +-pi where the along coordinate wraps, so a camera looking at that
// azimuth sees an evenly spaced mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "sim/net_geometry.h"
#include "sim/net_mesh.h"
#include "sim/render_cpu.h"
#include "tests/sim/sim_test_scenes.h"

namespace pensight::sim {
namespace {

// Net hit of the ray from the pen's centre towards azimuth `theta` at depth 4 m.
NetHit hit_at(const NetGeometry& net, double theta) {
  const Eigen::Vector3d o(0, 0, 4);
  const auto h = net.intersect(o, Eigen::Vector3d(std::cos(theta), std::sin(theta), 0));
  EXPECT_TRUE(h.has_value());
  return *h;
}

// Across the seam at azimuth +-pi, u jumps by a whole number of twine spacings in both twine
// families.
void expect_twines_continue_across_the_seam(const NetGeometry& net, const NetConfig& cfg) {
  const NetLattice lattice(cfg, net.u_around(), 1);
  // Two points 2 * delta * R apart on the wall, one each side of the seam.
  const double delta = 0.001;
  const NetHit a = hit_at(net, std::numbers::pi - delta),
               b = hit_at(net, -std::numbers::pi + delta);
  const Eigen::Vector2d step(b.u_m - a.u_m - 2 * delta * net.pen().radius_m * net.lattice_scale(),
                             b.v_m - a.v_m);
  for (const Eigen::Vector2d& n : {lattice.normal_a(), lattice.normal_b()}) {
    const double jump = n.dot(step) / lattice.period();
    EXPECT_NEAR(jump, std::round(jump), 1e-6);
  }
}

TEST(NetLattice, TwinePhaseContinuesAcrossAzimuthPi) {
  for (const auto& [type, angle_deg] :
       {std::pair{MeshType::kSquare, 90.0}, std::pair{MeshType::kSquare, 103.0},
        std::pair{MeshType::kDiamond, 90.0}, std::pair{MeshType::kDiamond, 75.0}}) {
    SCOPED_TRACE(std::string(to_string(type)) + " " + std::to_string(angle_deg));
    PenConfig pen;
    NetConfig cfg;
    cfg.mesh_type = type;
    cfg.opening_angle_deg = angle_deg;
    const NetGeometry net(pen, cfg);
    EXPECT_NEAR(net.lattice_scale(), 1.0, 1e-3);
    expect_twines_continue_across_the_seam(net, cfg);
  }
}

TEST(NetLattice, BulgeAcrossTheSeamIsContinuous) {
  PenConfig pen;
  NetConfig cfg;
  const double half = std::numbers::pi * pen.radius_m;
  cfg.bulges = {{half - 0.2, 4.0, 0.1, 0.5}};  // centred 0.2 m before the seam
  const NetGeometry net(pen, cfg);
  // 0.3 m past the seam is 0.5 m from the centre, the same as 0.7 m before the seam.
  EXPECT_NEAR(net.displacement(-half + 0.3, 4.0), net.displacement(half - 0.7, 4.0), 1e-12);
  EXPECT_GT(net.displacement(-half + 0.3, 4.0), 0.05);
}

// A fold (ridge or valley): the displacement is a tent of amplitude_m over radius_m to either
// side at every depth, its gradient the tent's slope, either sign (the ground truth's normal
// comes from it).
TEST(NetLattice, AFoldIsATentAndItsGradientItsSlope) {
  PenConfig pen;
  for (const double amplitude : {0.35, -0.35}) {
    NetConfig cfg;
    cfg.bulges = {{1.0, 4.0, amplitude, 1.5, true}};
    const NetGeometry net(pen, cfg);
    EXPECT_NEAR(net.displacement(1.0, 9.0), amplitude, 1e-12);
    EXPECT_NEAR(net.displacement(1.75, 4.0), amplitude / 2, 1e-12);
    EXPECT_EQ(net.displacement(2.6, 4.0), 0.0);
    for (const double along : {0.3, 0.9, 1.2, 2.2}) {
      const double h = 1e-6;
      const double slope =
          (net.displacement(along + h, 4.0) - net.displacement(along - h, 4.0)) / (2 * h);
      EXPECT_NEAR(net.displacement_gradient(along, 4.0).x(), slope, 1e-6) << amplitude;
      EXPECT_EQ(net.displacement_gradient(along, 4.0).y(), 0.0);
    }
  }
}

// A fold's panels hold the net unstretched: between two nearby points on the folded wall, u
// grows by their distance (x lattice_scale), where the wall's along grows up to 5.4 % less at a
// valley's line; beyond the fold, the twine pattern still closes around the pen.
TEST(NetLattice, AFoldsPanelsHoldTheNetUnstretched) {
  PenConfig pen;
  for (const double amplitude : {0.35, -0.35}) {
    SCOPED_TRACE(amplitude);
    NetConfig cfg;
    cfg.bulges = {{1.0, 4.0, amplitude, 1.5, true}};
    const NetGeometry net(pen, cfg);
    for (const double along : {-0.4, 0.2, 0.99, 1.01, 1.6, 2.4}) {
      const double step = 1e-4;
      const NetHit a = hit_at(net, along / pen.radius_m),
                   b = hit_at(net, (along + step) / pen.radius_m);
      const double length = (b.point - a.point).norm();
      EXPECT_NEAR((b.u_m - a.u_m) / net.lattice_scale(), length, 1e-4 * length)
          << amplitude << " at " << along;
    }
    EXPECT_NEAR(net.fold_arc_offset(-5), -net.fold_arc_offset(5), 1e-12);
    EXPECT_GT(net.fold_arc_offset(5), amplitude > 0 ? 0.0 : 0.03);
    expect_twines_continue_across_the_seam(net, cfg);
  }
}

// Column positions of the vertical twines: local maxima of the column means, to a sub-pixel.
std::vector<double> twine_columns(const ImageU8& img, double period_px) {
  std::vector<double> mean(static_cast<size_t>(img.width), 0.0);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) mean[static_cast<size_t>(x)] += img.at(x, y);
  }
  const int half = static_cast<int>(period_px / 3);
  std::vector<double> peaks;
  for (int x = half; x < img.width - half; ++x) {
    const auto begin = mean.begin() + x - half, end = mean.begin() + x + half + 1;
    if (*std::max_element(begin, end) != mean[static_cast<size_t>(x)]) continue;
    const double a = mean[static_cast<size_t>(x - 1)], b = mean[static_cast<size_t>(x)],
                 c = mean[static_cast<size_t>(x + 1)];
    peaks.push_back(x + 0.5 * (a - c) / (a - 2 * b + c));
  }
  return peaks;
}

TEST(NetLattice, MeshIsEvenAcrossAzimuthPiInTheImage) {
  // Facing the wall squarely at azimuth pi (along = pi R), camera 0.4 m from the net: the seam
  // runs down the middle of the image. The old code shifted the twines there by 0.27 mesh.
  const double camera_distance = 0.4;
  Scenario s = testing::one_pose(
      {.net_distance_m = camera_distance + 0.3, .along_m = std::numbers::pi * 12}, 360, 270);
  s.camera.samples_per_axis = 1;
  const NetGeometry net(s.pen, s.net);
  const RenderedFrame r =
      render_cpu(s, net, frame_state(s, 0), {.noise = false, .marine_snow = false});
  const double period = s.camera.calibration.camera.fx_px * s.net.bar_length_m / camera_distance;
  const std::vector<double> peaks = twine_columns(r.image, period);
  ASSERT_GE(peaks.size(), 15u);
  double worst = 0;
  for (size_t i = 1; i < peaks.size(); ++i) {
    worst = std::max(worst, std::abs((peaks[i] - peaks[i - 1]) / period - 1));
  }
  std::printf("  %zu twines, period %.2f px, worst spacing error %.1f %%\n", peaks.size(), period,
              100 * worst);
  EXPECT_LT(worst, 0.05);
}

}  // namespace
}  // namespace pensight::sim
