// Global pose per camera frame: the known-radius circle fit of the 30 ROI net points, the whole
// published node, and the fused estimator with one frame's worth of samples (camera 10 Hz, DVL
// 4 Hz with beam ranges, pressure 8 Hz, attitude 20 Hz). The published ROS node took 8.7 ms per
// update on a Jetson Orin. Floor: the fit is ~10 Gauss-Newton passes over 30 points (~6k flops);
// an EKF update of 13 states with numeric Jacobians is ~20 model evaluations and a few 13x13
// products (~10k flops), about 9 of them per frame (the net texture odometry's included).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "core/units.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"

namespace {

using namespace pensight;
using namespace pensight::global_pose;

constexpr double kRadius = kDefaultPenRadius_m;
constexpr int kFrames = 600;

Eigen::Isometry3d forward_mount(double x, double z) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  T.translation() = Eigen::Vector3d(x, 0, z);
  return T;
}

DvlCalibration dvl_config() {
  DvlCalibration dvl;
  dvl.T_body_dvl = forward_mount(0.4, 0.2);
  const double off = deg_to_rad(22.5);
  for (size_t i = 0; i < 4; ++i) {
    const double az = std::numbers::pi / 4 + static_cast<double>(i) * std::numbers::pi / 2;
    dvl.beam_directions_S[i] = {std::sin(off) * std::cos(az), std::sin(off) * std::sin(az),
                                std::cos(off)};
  }
  return dvl;
}

// One frame's samples along a pass 1.3 m from the wall at 0.3 m/s, consistent with each other.
struct Frame {
  NetObservation camera;
  std::vector<DvlSample> dvl;
  std::vector<PressureSample> depth;
  std::vector<AttitudeSample> attitude;
};

Eigen::Isometry3d pose_at(double t) {
  const double rho = 0.3 * t / (kRadius - 1.3), r = kRadius - 1.3 - 0.3 * std::sin(t / 6);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_from_rpy(0, 0, rho + 0.1 * std::sin(t / 4));
  T.translation() = Eigen::Vector3d(r * std::cos(rho), r * std::sin(rho), 5.0);
  return T;
}

// The optical axis' net point's move from t0 to t1 over a square 30 mm mesh (net_texture.h).
TextureStep texture_step_at(double t0, double t1, const Eigen::Isometry3d& T_bc) {
  const auto axis_point = [&](double t) {
    const Eigen::Isometry3d T = pose_at(t) * T_bc;
    const Eigen::Vector3d dir = T.linear().col(2);
    return Eigen::Vector3d(T.translation() +
                           ray_to_cylinder(T.translation(), dir, kRadius).value_or(0) * dir);
  };
  const Eigen::Vector3d a = axis_point(t0), b = axis_point(t1);
  const double azimuth = std::atan2(b.y(), b.x()), bar = 0.030;
  const Eigen::Matrix3d R_camera_pen = (pose_at(t1) * T_bc).linear().transpose();
  TextureStep s;
  s.valid = true;
  s.from_ns = seconds_to_ns(t0);
  s.bars_C = {bar * R_camera_pen * Eigen::Vector3d(-std::sin(azimuth), std::cos(azimuth), 0),
              bar * R_camera_pen * Eigen::Vector3d::UnitZ()};
  const double moved[2] = {kRadius * wrap_angle(azimuth - std::atan2(a.y(), a.x())) / bar,
                           (b.z() - a.z()) / bar};
  for (size_t i = 0; i < 2; ++i) s.moved_bars[i] = moved[i] - std::floor(moved[i] + 0.5);
  return s;
}

std::vector<Frame> make_frames() {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  const PinholeCamera cam;
  const Eigen::Isometry3d T_bc = forward_mount(0.3, 0.1);
  const DvlCalibration dvl = dvl_config();
  std::vector<Frame> frames(kFrames);
  for (int f = 0; f < kFrames; ++f) {
    const double t = 0.1 * f;
    Frame& fr = frames[static_cast<size_t>(f)];
    fr.camera.t_ns = seconds_to_ns(t);
    const Eigen::Isometry3d T_pc = pose_at(t) * T_bc;
    for (int i = 0; i < 30; ++i) {
      const Eigen::Vector3d dir =
          cam.ray({150.0 + (i % 6) * 84.0, 150.0 + (i / 6) * 60.0}).normalized();
      const auto d = ray_to_cylinder(T_pc.translation(), T_pc.linear() * dir, kRadius);
      const double outlier = i % 10 == 3 ? 0.4 : 0.0;
      fr.camera.points_C.push_back(dir * (d ? *d * (1 + 0.015 * n01(rng)) + outlier : kNaN));
    }
    const auto rel = net_relative_pose(T_pc, NetWall::cylinder(kRadius));
    fr.camera.d_net_m = rel.d_net_m;
    fr.camera.psi_net_rad = rel.psi_net_rad;
    if (f > 0) fr.camera.texture = texture_step_at(t - 0.1, t, T_bc);
    for (const double s : {t + 0.007, t + 0.057}) {
      const Eigen::Matrix3d R = pose_at(s).linear();
      fr.attitude.push_back({seconds_to_ns(s), 0.0, 0.0, std::atan2(R(1, 0), R(0, 0)) + 0.5});
    }
    if (f % 4 == 0 || f % 4 == 2) {
      const double s = t + 0.013, h = 1e-4;
      const Eigen::Isometry3d T = pose_at(s);
      const Eigen::Vector3d v_pen =
          (pose_at(s + h).translation() - pose_at(s - h).translation()) / (2 * h);
      DvlSample d;
      d.timestamp_ns = seconds_to_ns(s);
      d.valid = true;
      d.velocity_B_mps =
          T.linear().transpose() * v_pen + 0.01 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
      d.beam_range_m = dvl_ranges_to_wall(dvl, T, NetWall::cylinder(kRadius));
      fr.dvl.push_back(d);
    }
    if (f % 4 != 3) fr.depth.push_back({seconds_to_ns(t + 0.031), 5.0 + 0.02 * n01(rng)});
  }
  return frames;
}

const std::vector<Frame>& frames() {
  static const std::vector<Frame> f = make_frames();
  return f;
}

void BM_CircleFit(benchmark::State& state) {
  const auto& obs = frames()[100].camera;
  const auto xy = horizontal_net_points(obs.points_C, forward_mount(0.3, 0.1));
  CircleFitOptions o;
  o.radius_m = kRadius;
  for (auto _ : state) {
    const CircleFit fit = fit_circle_known_radius(xy, o);
    benchmark::DoNotOptimize(fit.centre.data());
  }
}
BENCHMARK(BM_CircleFit)->Unit(benchmark::kMicrosecond);

void BM_PublishedNode_PerFrame(benchmark::State& state) {
  PublishedGlobalPoseConfig cfg;
  cfg.pen_radius_m = kRadius;
  cfg.T_body_camera = forward_mount(0.3, 0.1);
  PublishedGlobalPose node(cfg);
  size_t f = 0;
  for (auto _ : state) {
    const Frame& fr = frames()[f];
    for (const auto& s : fr.attitude) node.add(s);
    for (const auto& s : fr.dvl) node.add(s);
    for (const auto& s : fr.depth) node.add(s);
    const GlobalPose g = node.add(fr.camera);
    benchmark::DoNotOptimize(g.r_g_m);
    f = (f + 1) % frames().size();
  }
}
BENCHMARK(BM_PublishedNode_PerFrame)->Unit(benchmark::kMicrosecond);

// Fused estimator: adding a frame's samples and asking for the frame's estimate. Restarts (a new
// estimator) every kFrames frames, less than 0.2 % of the iterations. Arg: the net texture
// odometry off (0) or on (1).
void BM_Estimator_PerFrame(benchmark::State& state) {
  GlobalPoseEstimatorConfig cfg;
  cfg.pen_radius_m = kRadius;
  cfg.T_body_camera = forward_mount(0.3, 0.1);
  cfg.dvl_beams = dvl_config();
  cfg.use_net_texture = state.range(0) != 0;
  auto est = std::make_unique<GlobalPoseEstimator>(cfg);
  size_t f = 0;
  for (auto _ : state) {
    const Frame& fr = frames()[f];
    for (const auto& s : fr.attitude) est->add(s);
    for (const auto& s : fr.dvl) est->add(s);
    for (const auto& s : fr.depth) est->add(s);
    est->add(fr.camera);
    const GlobalPose g = est->estimate(fr.camera.t_ns);
    benchmark::DoNotOptimize(g.r_g_m);
    if (++f == frames().size()) {
      f = 0;
      est = std::make_unique<GlobalPoseEstimator>(cfg);
    }
  }
}
BENCHMARK(BM_Estimator_PerFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
