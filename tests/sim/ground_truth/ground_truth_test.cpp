// Ground truth is self-consistent with the rendered images: the net period measured by FFT in
// the image matches fx * mesh / d_net, and psi_net / pitch_net / d_net match a plane fitted to
// the depth map, with the contract's signs.
#include <fftw3.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "sim/ground_truth.h"
#include "sim/render_cpu.h"
#include "tests/sim/sim_test_scenes.h"

namespace pensight::sim {
namespace {

constexpr int kPatch = 256;  // the central 256x256 patch of the 720x540, fx = 462 camera
constexpr int kPad = 1024;   // zero padding: 1/1024 cycles per pixel between FFT bins

// Period in pixels of the strongest horizontal and vertical frequency of the image.
Eigen::Vector2d measured_periods_px(const ImageU8& img) {
  std::vector<float> in(static_cast<size_t>(kPad) * kPad, 0.0f);
  double mean = 0;
  for (uint8_t v : img.pixels) mean += v;
  mean /= static_cast<double>(img.pixels.size());
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double wx = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * (x + 0.5) / img.width);
      const double wy = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * (y + 0.5) / img.height);
      in[static_cast<size_t>(y) * kPad + x] = static_cast<float>((img.at(x, y) - mean) * wx * wy);
    }
  }
  const int cols = kPad / 2 + 1;
  std::vector<fftwf_complex> out(static_cast<size_t>(kPad) * cols);
  fftwf_plan plan = fftwf_plan_dft_r2c_2d(kPad, kPad, in.data(), out.data(), FFTW_ESTIMATE);
  fftwf_execute(plan);
  fftwf_destroy_plan(plan);
  auto mag = [&](int ky, int kx) {
    const auto& c = out[static_cast<size_t>(ky) * cols + kx];
    return std::log(std::hypot(c[0], c[1]) + 1e-12);
  };
  // Peak on an axis, refined by a parabola through the log magnitudes (exact for a Gaussian).
  auto peak = [&](bool horizontal) {
    int best = 8;
    for (int k = 8; k < kPad / 2; ++k) {
      const double m = horizontal ? mag(0, k) : mag(k, 0);
      if (m > (horizontal ? mag(0, best) : mag(best, 0))) best = k;
    }
    const double a = horizontal ? mag(0, best - 1) : mag(best - 1, 0);
    const double b = horizontal ? mag(0, best) : mag(best, 0);
    const double c = horizontal ? mag(0, best + 1) : mag(best + 1, 0);
    const double k = best + 0.5 * (a - c) / (a - 2 * b + c);
    return kPad / k;
  };
  return {peak(true), peak(false)};
}

TEST(GroundTruth, NetPeriodInImageMatchesFocalTimesMeshOverDistance) {
  for (const double camera_distance : {0.4, 0.6, 1.0, 1.5, 2.0, 2.5}) {
    const Scenario s = testing::one_pose({.net_distance_m = camera_distance + 0.3}, kPatch, kPatch,
                                         "{shape: cylinder, radius_m: 12, depth_m: 15}", "",
                                         ", intrinsics: [462, 462, 127.5, 127.5]");
    const NetGeometry net(s.pen, s.net);
    const FrameState f = frame_state(s, 0);
    const RenderedFrame r = render_cpu(s, net, f);  // with noise and marine snow
    const double d_net = net_relative(s, net, f.T_pen_camera).d_net_m;
    ASSERT_NEAR(d_net, camera_distance, 1e-9);
    const double expected = 462.0 * s.net.bar_length_m / d_net;
    const Eigen::Vector2d got = measured_periods_px(r.image);
    std::printf("  d_net %.2f m: period expected %.3f px, measured %.3f / %.3f px\n", d_net,
                expected, got.x(), got.y());
    EXPECT_NEAR(got.x() / expected, 1.0, 0.02) << "horizontal, d_net " << d_net;
    EXPECT_NEAR(got.y() / expected, 1.0, 0.02) << "vertical, d_net " << d_net;
  }
}

struct PlaneFit {
  double psi, pitch, d;
};

// z = a x + b y + c through the net points of the depth map (camera frame), pixels within
// `half_window` of the principal point.
PlaneFit fit_plane(const Scenario& s, const ImageF32& depth, int half_window) {
  const PinholeCamera& cam = s.camera.calibration.camera;
  std::vector<Eigen::Vector3d> pts;
  for (int y = 0; y < depth.height; ++y) {
    for (int x = 0; x < depth.width; ++x) {
      const float z = depth.at(x, y);
      if (!(z > 0) || std::abs(x - cam.cx_px) > half_window ||
          std::abs(y - cam.cy_px) > half_window) {
        continue;
      }
      pts.push_back(cam.ray({static_cast<double>(x), static_cast<double>(y)}) * z);
    }
  }
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    A.row(static_cast<Eigen::Index>(i)) << pts[i].x(), pts[i].y(), 1.0;
    b(static_cast<Eigen::Index>(i)) = pts[i].z();
  }
  const Eigen::Vector3d abc = A.colPivHouseholderQr().solve(b);
  return {std::atan(abc.x()), std::atan(abc.y()), abc.z()};
}

struct Case {
  const char* pen;
  testing::Pose pose;
  int half_window;
  double tol_rad;
};

TEST(GroundTruth, NetAnglesAgreeWithPlaneFittedToDepth) {
  const char* tank =
      "{shape: plane, radius_m: 100, width_m: 8, top_m: 0.2, height_m: 6, wall_gap_m: 1}";
  const char* pen = "{shape: cylinder, radius_m: 12, depth_m: 15}";
  const Case cases[] = {
      {tank, {.net_distance_m = 1.3, .heading_rad = 0.3, .depth_m = 3}, 1000, 2e-3},
      {tank,
       {.net_distance_m = 1.0, .heading_rad = -0.2, .pitch_rad = -0.25, .depth_m = 3},
       1000,
       2e-3},
      {pen, {.net_distance_m = 1.3, .heading_rad = 0.35, .pitch_rad = 0.15}, 25, 1e-2},
      {pen, {.net_distance_m = 2.0, .heading_rad = -0.25, .pitch_rad = -0.2}, 25, 1e-2},
  };
  for (const Case& c : cases) {
    const Scenario s = testing::one_pose(c.pose, 180, 135, c.pen);
    const NetGeometry net(s.pen, s.net);
    const FrameState f = frame_state(s, 0);
    const RenderedFrame r = render_cpu(s, net, f);
    const NetRelative truth = net_relative(s, net, f.T_pen_camera);
    const PlaneFit fit = fit_plane(s, r.depth_m, c.half_window);
    SCOPED_TRACE(std::string(c.pen) + " heading " + std::to_string(c.pose.heading_rad));
    EXPECT_NEAR(truth.psi_net_rad, fit.psi, c.tol_rad);
    EXPECT_NEAR(truth.pitch_net_rad, fit.pitch, c.tol_rad);
    EXPECT_NEAR(truth.d_net_m, fit.d, 5e-3);
  }
}

TEST(GroundTruth, SignsFollowTheContract) {
  // Flat net straight ahead; turned right -> psi_net > 0; nose down -> pitch_net > 0.
  const char* tank =
      "{shape: plane, radius_m: 100, width_m: 8, top_m: 0.2, height_m: 6, wall_gap_m: 1}";
  auto rel = [&](const testing::Pose& p) {
    const Scenario s = testing::one_pose(p, 180, 135, tank);
    return net_relative(s, NetGeometry(s.pen, s.net), frame_state(s, 0).T_pen_camera);
  };
  const NetRelative right = rel({.net_distance_m = 1.3, .heading_rad = 0.3, .depth_m = 3});
  EXPECT_NEAR(right.psi_net_rad, 0.3, 1e-9);
  EXPECT_NEAR(right.pitch_net_rad, 0.0, 1e-9);
  // The camera rides 0.3 m ahead of the body origin, so turning moves it too.
  EXPECT_NEAR(right.d_net_m, (1.3 - 0.3 * std::cos(0.3)) / std::cos(0.3), 1e-9);
  const NetRelative down = rel({.net_distance_m = 1.3, .pitch_rad = -0.2, .depth_m = 3});
  EXPECT_NEAR(down.pitch_net_rad, 0.2, 1e-9);
  EXPECT_NEAR(down.psi_net_rad, 0.0, 1e-9);
  const NetRelative away = rel({.net_distance_m = 1.3, .heading_rad = 3.0, .depth_m = 3});
  EXPECT_TRUE(std::isnan(away.d_net_m));
}

}  // namespace
}  // namespace pensight::sim
