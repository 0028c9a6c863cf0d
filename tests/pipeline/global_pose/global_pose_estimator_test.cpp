#include "pipeline/global_pose/global_pose_estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "core/error.h"
#include "core/log.h"
#include "pipeline/global_pose/attitude_series.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "tests/pipeline/global_pose/pen_sim.h"
#include "tests/support/log_capture.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/evaluation/evaluation.h"

namespace pensight::global_pose {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Errors of one run against the truth. rho_g and psi_g are compared as changes from the first
// frame (the pen's azimuth origin is not observable; dataset-format.md).
struct Errors {
  std::vector<double> t_s, r_m, psi_rad, z_m, arc_m;  // arc_m: signed rho error x r
  double path_m = 0;
  // The lock rule (lock_rule.h) may refuse the first fixes and wait for a better one: those
  // frames have no estimate and are counted apart from NaN rows after the filter has locked.
  int frames_before_lock = 0;
  int nan_rows = 0;

  // The definition `pensight evaluate` uses (evaluation.h).
  double drift_per_m() const { return rho_drift_per_m(t_s, arc_m, path_m); }
};

class ErrorCollector {
 public:
  void add(const GlobalPose& g, const sim::Pose& truth) {
    if (!prev_.empty()) e_.path_m += (truth.p_pen.head<2>() - prev_.back().p_pen.head<2>()).norm();
    prev_.assign(1, truth);
    if (!std::isfinite(g.r_g_m) || !std::isfinite(g.rho_g_rad) || !std::isfinite(g.psi_g_rad)) {
      ++(e_.t_s.empty() ? e_.frames_before_lock : e_.nan_rows);
      return;
    }
    if (std::isnan(rho0_est_)) {
      rho0_est_ = g.rho_g_rad;
      rho0_true_ = truth.rho_rad();
    }
    const double drho = wrap_angle((g.rho_g_rad - rho0_est_) - (truth.rho_rad() - rho0_true_));
    e_.t_s.push_back(truth.t_s);
    e_.r_m.push_back(std::abs(g.r_g_m - truth.r_m()));
    e_.arc_m.push_back(drho * truth.r_m());
    e_.psi_rad.push_back(
        std::abs(wrap_angle((g.psi_g_rad - rho0_est_) - (truth.yaw_rad - rho0_true_))));
    if (std::isfinite(g.z_g_m)) e_.z_m.push_back(std::abs(g.z_g_m - truth.p_pen.z()));
  }
  const Errors& errors() const { return e_; }

 private:
  Errors e_;
  std::vector<sim::Pose> prev_;
  double rho0_est_ = kNaN, rho0_true_ = kNaN;
};

GlobalPoseEstimatorConfig estimator_config(double radius) {
  GlobalPoseEstimatorConfig cfg;
  cfg.pen_radius_m = radius;
  cfg.T_body_camera = sim::forward_camera();
  cfg.dvl_beams = sim::forward_dvl();
  return cfg;
}

// Clean simulated frames lock at once or within a few frames: a fix is refused when an outlier
// ROI slips into the circle fit's inliers (2000 seeds: 1 frame in ~0.4 % of the sequences).
// Once locked, every frame has an estimate. `refused_by_design`: leading frames the test made
// unlockable on purpose.
void expect_locked_quickly(const Errors& e, int refused_by_design = 0) {
  EXPECT_LE(e.frames_before_lock, refused_by_design + 5);
  EXPECT_EQ(e.nan_rows, 0);
}

// The default simulated trajectory of this length with default sensor noise, on a fresh seed.
sim::Sequence fresh_sequence(double duration_s) {
  sim::Trajectory traj;
  traj.duration_s = duration_s;
  std::mt19937_64 rng(testing::fresh_seed());
  return sim::make_sequence(traj, {}, rng());
}

// Feeds the sequence in timestamp order, asking for the estimate at each camera frame.
Errors run_estimator(const sim::Sequence& seq, GlobalPoseEstimator& est) {
  ErrorCollector c;
  sim::Visitor v;
  v.dvl = [&](const DvlSample& s) { est.add(s); };
  v.depth = [&](const PressureSample& s) { est.add(s); };
  v.attitude = [&](const AttitudeSample& s) { est.add(s); };
  v.camera = [&](const NetObservation& obs, const sim::Pose& truth) {
    est.add(obs);
    c.add(est.estimate(obs.t_ns), truth);
  };
  sim::replay(seq, v);
  return c.errors();
}

Errors run_published(const sim::Sequence& seq, double radius) {
  PublishedGlobalPoseConfig cfg;
  cfg.pen_radius_m = radius;
  cfg.T_body_camera = sim::forward_camera();
  PublishedGlobalPose node(cfg);
  ErrorCollector c;
  sim::Visitor v;
  v.dvl = [&](const DvlSample& s) { node.add(s); };
  v.depth = [&](const PressureSample& s) { node.add(s); };
  v.camera = [&](const NetObservation& obs, const sim::Pose& truth) {
    c.add(node.add(obs), truth);
  };
  sim::replay(seq, v);
  return c.errors();
}

TEST(GlobalPoseEstimator, AccuracyAndDriftVersusPublished) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0, 100.0}) {
    sim::Trajectory traj;
    traj.radius_m = radius;
    traj.roll_pitch_amp_rad = 3 * kDeg;
    const sim::SensorNoise noise;
    const sim::Sequence seq = sim::make_sequence(traj, noise, rng());
    GlobalPoseEstimator est(estimator_config(radius));
    const Errors e = run_estimator(seq, est);
    const Errors p = run_published(seq, radius);
    std::printf(
        "R = %5.1f m, %.0f m travelled:\n"
        "  estimator: r_g median %.4f p95 %.4f m, psi_g median %.3f deg, z p99 %.4f m, "
        "drift %.3f %% of distance\n"
        "  published: r_g median %.4f p95 %.4f m, psi_g median %.3f deg, drift %.3f %%\n",
        radius, e.path_m, sim::median(e.r_m), sim::percentile(e.r_m, 0.95),
        sim::median(e.psi_rad) / kDeg, sim::percentile(e.z_m, 0.99), 100 * e.drift_per_m(),
        sim::median(p.r_m), sim::percentile(p.r_m, 0.95), sim::median(p.psi_rad) / kDeg,
        100 * p.drift_per_m());
    const auto c = est.counters();
    std::printf("  gated out: DVL %d, plane %d, depth %d, yaw %d, fix %d, d_net %d\n",
                c.dvl_velocity.rejected, c.dvl_plane.rejected, c.depth.rejected,
                c.attitude.rejected, c.vision_fix.rejected, c.vision_relative.rejected);
    expect_locked_quickly(e);
    EXPECT_LE(sim::median(e.r_m), 0.03);
    EXPECT_LE(sim::percentile(e.r_m, 0.95), 0.08);
    EXPECT_LE(sim::median(e.psi_rad) / kDeg, 1.5);
    EXPECT_LE(sim::percentile(e.z_m, 0.99), 3 * noise.depth_sigma_m);
    // Vision sees rho_g through the heading, psi_g - psi_r, which is worth radius x heading error
    // of arc: on the flat net (100 m) the estimator leans on the DVL as the published node does.
    // 2000 seeds, estimator / published drift: median 0.025, 0.040, 0.13; worst 0.13, 0.21, 0.63.
    EXPECT_LE(e.drift_per_m(), (radius < 50 ? 0.5 : 0.8) * p.drift_per_m());
    // Good data is rarely gated out (p = 0.001 per sample, plus the ROI outliers' effect).
    EXPECT_LE(c.dvl_velocity.rejected, 10);
    EXPECT_LE(c.vision_fix.rejected, 24);
    // The covariance is reported and finite.
    const GlobalPose last = est.estimate(seq.camera.back().t_ns);
    EXPECT_TRUE(last.covariance.allFinite());
    EXPECT_GT(last.covariance(0, 0), 0);
    EXPECT_LT(std::sqrt(last.covariance(0, 0)), 0.05);
  }
}

// Largest |a - b| of two runs' arc errors over frames in [t0, t1].
double max_difference(const Errors& a, const Errors& b, double t0, double t1) {
  double m = 0;
  for (size_t i = 0; i < a.t_s.size() && i < b.t_s.size(); ++i)
    if (a.t_s[i] >= t0 && a.t_s[i] <= t1) m = std::max(m, std::abs(a.arc_m[i] - b.arc_m[i]));
  return m;
}

// A DVL velocity spike (2 m/s for 0.5 s, as in the published low-light run) is gated out: 2 s
// later the estimate is within 4 cm of the same run without the spike, while the published rho_g
// keeps the jump. What is left is along the net: for 0.5 s no DVL velocity was used, and vision
// cannot observe rho_g; with an ROV's process noise (pen_ekf.h) 1001 seeds left median 5.7 mm,
// 99.9th percentile 24 mm, worst 26 mm.
TEST(GlobalPoseEstimator, DvlSpikeIsRejectedAndRecoversWithin2s) {
  std::mt19937_64 rng(testing::fresh_seed());
  const double radius = 12.0;
  sim::Trajectory traj;
  traj.duration_s = 80;
  const sim::Sequence clean = sim::make_sequence(traj, {}, rng());
  sim::Sequence spiked = clean;
  const double t_spike = 60.0;
  int n_spiked = 0;
  for (auto& s : spiked.dvl) {
    const double t = seconds_between(sim::kStart_ns, s.timestamp_ns);
    if (t >= t_spike && t < t_spike + 0.5) {
      s.velocity_B_mps += Eigen::Vector3d(0.8, 1.8, 0.3);
      ++n_spiked;
    }
  }
  ASSERT_EQ(n_spiked, 2);
  GlobalPoseEstimator est_clean(estimator_config(radius)), est(estimator_config(radius));
  const Errors e_clean = run_estimator(clean, est_clean);
  const Errors e = run_estimator(spiked, est);
  const Errors p_clean = run_published(clean, radius), p = run_published(spiked, radius);
  const double during = max_difference(e, e_clean, t_spike, t_spike + 2);
  const double after = max_difference(e, e_clean, t_spike + 2, traj.duration_s);
  const double pub_after = max_difference(p, p_clean, t_spike + 2, traj.duration_s);
  std::printf(
      "DVL spike: estimator moved %.4f m within 2 s, %.4f m after; published %.3f m "
      "after; DVL samples gated out %d\n",
      during, after, pub_after, est.counters().dvl_velocity.rejected);
  EXPECT_GE(est.counters().dvl_velocity.rejected, 2);
  EXPECT_LE(after, 0.04);
  EXPECT_GT(pub_after, 0.5);  // the published node keeps a ~0.9 m jump
}

// Following the net at 0.2 m/s, 0.85-1.25 m from it, with a vehicle's sensors: DVL 5 mm/s
// without bias, attitude 0.2 deg without drift.
sim::Sequence following_sequence(double radius_m, double duration_s, uint64_t seed) {
  sim::Trajectory traj;
  traj.radius_m = radius_m;
  traj.duration_s = duration_s;
  traj.speed_mps = 0.2;
  traj.mean_distance_m = 1.05;
  traj.distance_amp_m = 0.2;
  traj.psi_r_amp_rad = 0.06;
  sim::SensorNoise noise;
  noise.dvl_sigma_mps = 0.005;
  noise.dvl_scale_error = 0;
  noise.dvl_bias_mps.setZero();
  noise.yaw_sigma_rad = 0.0035;
  noise.attitude_sigma_rad = 0.0035;
  noise.yaw_drift_radps = 0;
  return sim::make_sequence(traj, noise, seed);
}

// The along-net position over 15 s of following with a vehicle's sensors (DVL 5 mm/s, attitude
// yaw 0.2 deg, no DVL bias) and DVL spikes of 0.3-0.8 m/s in each axis: every spiked sample is
// rejected and counted, and the along-net error stays within 10 cm (a 0.8 m/s spike let through
// for 0.5 s moves it by 40 cm). Over 200 seeds (PENSIGHT_TEST_SEED=1000..1199) its maximum was
// median 2.4 / 1.8 cm, p95 4.4 / 3.5 cm, worst 5.1 / 5.7 cm (12 / 25 m) with the quiet process
// noise while following (motion_schedule.h); 5.4 / 5.7, 9.0 / 9.9 and 14.9 / 12.7 cm on the
// same seeds without it. These points (1.5 % range noise, 10 % outliers) are noisier than the
// renders' fixes.
TEST(GlobalPoseEstimator, AlongNetOver15sAndEverySpikeRejected) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0}) {
    sim::Sequence seq = following_sequence(radius, 15, rng());
    struct Spike {
      double t_s, duration_s;
      Eigen::Vector3d v;
    };
    const Spike spikes[] = {
        {4.0, 0.25, {0, 0.5, 0}}, {8.0, 0.5, {-0.8, 0, 0}}, {12.0, 0.25, {0, 0, 0.3}}};
    int n_spiked = 0;
    for (auto& s : seq.dvl) {
      const double t = seconds_between(sim::kStart_ns, s.timestamp_ns);
      for (const Spike& k : spikes) {
        if (t >= k.t_s && t < k.t_s + k.duration_s) {
          s.velocity_B_mps += k.v;
          ++n_spiked;
        }
      }
    }
    ASSERT_EQ(n_spiked, 4);
    GlobalPoseEstimator est(estimator_config(radius));
    const Errors e = run_estimator(seq, est);
    double worst = 0;
    for (const double a : e.arc_m) worst = std::max(worst, std::abs(a));
    std::printf("R = %.0f m: along-net error max %.4f m over 15 s; spikes rejected %d\n", radius,
                worst, est.counters().dvl_velocity.spikes);
    EXPECT_LE(worst, 0.10) << "R = " << radius;
    EXPECT_EQ(est.counters().dvl_velocity.spikes, n_spiked) << "R = " << radius;
  }
}

// Along the net with the net texture odometry: the optical axis' net point's move in bars, 0.01
// bar (0.3 mm) of phase noise per frame, the DVL and attitude noise and spikes of the test above,
// 60 s. Over 200 seeds (PENSIGHT_TEST_SEED=1000..1199) the largest change of the along-net error
// within 15 s was median 1.5 / 1.5 cm, p99 2.4 / 2.0 cm, worst 2.5 / 2.2 cm (12 / 25 m), the drift
// worst 0.17 / 0.19 %, and at most one step in 599 was not counted. What is left is the heading's
// error (0.2-0.5 deg with these noisier fixes) times the camera's 1.3 m to the net; on the renders
// (docs/global_pose.md) the 2 cm holds. Without the odometry: 5.4 / 5.9 cm median.
TEST(GlobalPoseEstimator, AlongNetWithNetTextureOver60s) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0}) {
    sim::Sequence seq = following_sequence(radius, 60, rng());
    sim::add_texture_steps(seq, radius, sim::forward_camera(), 0.03, 0.01, rng);
    int n_spiked = 0;
    for (auto& s : seq.dvl) {
      const double t = seconds_between(sim::kStart_ns, s.timestamp_ns);
      if ((t >= 14.0 && t < 14.25) || (t >= 38.0 && t < 38.5)) {
        s.velocity_B_mps += Eigen::Vector3d(0, t < 20 ? 0.5 : 0.0, t < 20 ? 0.0 : 0.3);
        ++n_spiked;
      }
    }
    ASSERT_EQ(n_spiked, 3);
    GlobalPoseEstimator est(estimator_config(radius));
    const Errors e = run_estimator(seq, est);
    double worst = 0;  // the largest change of the along-net error within 15 s
    for (size_t i = 0; i < e.arc_m.size(); ++i)
      for (size_t j = i; j < e.arc_m.size() && e.t_s[j] - e.t_s[i] <= 15.0; ++j)
        if (std::isfinite(e.arc_m[i]) && std::isfinite(e.arc_m[j]))
          worst = std::max(worst, std::abs(e.arc_m[j] - e.arc_m[i]));
    const GlobalPoseCounters c = est.counters();
    std::printf(
        "R = %.0f m: along-net error over any 15 s %.4f m, drift %.4f %%; texture steps "
        "%d accepted of %d; spikes rejected %d\n",
        radius, worst, 100 * e.drift_per_m(), c.net_texture.accepted, c.net_texture.received,
        c.dvl_velocity.spikes);
    EXPECT_LE(worst, 0.03) << "R = " << radius;
    EXPECT_LE(e.drift_per_m(), 0.003) << "R = " << radius;
    EXPECT_EQ(c.dvl_velocity.spikes, n_spiked) << "R = " << radius;
    EXPECT_GE(c.net_texture.accepted, static_cast<int>(seq.camera.size()) - 5) << "R = " << radius;
  }
}

// A frame whose net points are all 0.4 m too far (a consistent but wrong circle) is rejected.
TEST(GlobalPoseEstimator, BadVisionFrameIsRejected) {
  sim::Sequence seq = fresh_sequence(30);
  const size_t bad = 200;
  for (auto& p : seq.camera[bad].points_C) p *= (p.norm() + 0.4) / p.norm();
  GlobalPoseEstimator est(estimator_config(12.0));
  const Errors e = run_estimator(seq, est);
  EXPECT_GE(est.counters().vision_fix.rejected, 1);
  EXPECT_LE(e.r_m[bad], 0.05);
}

TEST(GlobalPoseEstimator, RunsWithoutDvlAndSaysSo) {
  sim::Sequence seq = fresh_sequence(60);
  seq.dvl.clear();
  testing::LogCapture log(LogLevel::kWarning);
  auto cfg = estimator_config(12.0);
  cfg.has_dvl = false;
  GlobalPoseEstimator est(cfg);
  const Errors e = run_estimator(seq, est);
  EXPECT_NE(log.text().find("no DVL"), std::string::npos) << log.text();
  // Heading aiding (attitude yaw) and the vision fixes still give all four values. Without the
  // DVL nothing refines the yaw bias set at the lock from one attitude sample and one fix, so
  // psi_g keeps their error: the run's median error over 600 seeds was median 0.35 deg, 99th
  // percentile 1.03 deg, worst 1.25 deg (one of ~3000 CI seeds: 1.65 deg).
  expect_locked_quickly(e);
  std::printf("without DVL: r_g median %.4f m, psi_g median %.3f deg, arc error end %.3f m\n",
              sim::median(e.r_m), sim::median(e.psi_rad) / kDeg, e.arc_m.back());
  EXPECT_LE(sim::median(e.r_m), 0.03);
  EXPECT_LE(sim::median(e.psi_rad) / kDeg, 2.0);
}

TEST(GlobalPoseEstimator, NaNVelocitiesAreSkippedAndCounted) {
  sim::Sequence seq = fresh_sequence(40);
  int spoiled = 0;
  for (size_t i = 0; i < seq.dvl.size(); i += 3) {
    if (i % 2 == 0) {
      seq.dvl[i].velocity_B_mps.x() = kNaN;
    } else {
      seq.dvl[i].valid = false;
    }
    ++spoiled;
  }
  testing::LogCapture log(LogLevel::kWarning);
  GlobalPoseEstimator est(estimator_config(12.0));
  const Errors e = run_estimator(seq, est);
  EXPECT_EQ(est.counters().dvl_velocity.invalid, spoiled);
  EXPECT_NE(log.text().find("NaN DVL velocity"), std::string::npos) << log.text();
  expect_locked_quickly(e);
  EXPECT_LE(sim::median(e.r_m), 0.03);
  EXPECT_LE(sim::median(e.psi_rad) / kDeg, 1.5);
}

// Texture steps with NaN in their moves, bars or ray (an embedding caller's bad input) are
// counted as invalid and leave the estimate as good as the clean steps around them.
TEST(GlobalPoseEstimator, NaNTextureStepsAreSkippedAndCounted) {
  std::mt19937_64 rng(testing::fresh_seed());
  sim::Sequence seq = following_sequence(12.0, 20, rng());
  sim::add_texture_steps(seq, 12.0, sim::forward_camera(), 0.03, 0.01, rng);
  int spoiled = 0;
  for (size_t i = 20; i < seq.camera.size(); i += 25) {
    TextureStep& s = seq.camera[i].texture;
    if (spoiled % 3 == 0) s.moved_bars[1] = kNaN;
    if (spoiled % 3 == 1) s.bars_C[0].x() = kNaN;
    if (spoiled % 3 == 2) s.ray_C.y() = kNaN;
    ++spoiled;
  }
  GlobalPoseEstimator est(estimator_config(12.0));
  const Errors e = run_estimator(seq, est);
  const SensorCounters c = est.counters().net_texture;
  // Beside the spoiled ones, a clean step is refused as ambiguous now and then (at most 5 in 599
  // in AlongNetWithNetTextureOver60s).
  EXPECT_GE(c.invalid, spoiled);
  EXPECT_LE(c.invalid, spoiled + 3);
  for (size_t i = 0; i < e.arc_m.size(); ++i) {
    ASSERT_TRUE(std::isfinite(e.r_m[i]) && std::isfinite(e.arc_m[i])) << "frame " << i;
    EXPECT_LE(std::abs(e.arc_m[i]), 0.03) << "frame " << i;
  }
}

TEST(GlobalPoseEstimator, RunsWithoutAttitudeAndSaysSo) {
  sim::Sequence seq = fresh_sequence(60);
  seq.attitude.clear();
  testing::LogCapture log(LogLevel::kWarning);
  auto cfg = estimator_config(12.0);
  cfg.has_attitude = false;
  GlobalPoseEstimator est(cfg);
  const Errors e = run_estimator(seq, est);
  EXPECT_NE(log.text().find("no attitude"), std::string::npos) << log.text();
  // rho_g from the DVL alone: produced, drifting like the published method's.
  expect_locked_quickly(e);
  EXPECT_LE(sim::median(e.r_m), 0.03);
  std::printf("without attitude: r_g median %.4f m, drift %.3f %%\n", sim::median(e.r_m),
              100 * e.drift_per_m());
}

// Neither DVL nor attitude: nothing constrains rho_g, which is NaN from max_unaided_s after the
// lock (where it was set to initial_rho_rad); r_g and z_g remain.
TEST(GlobalPoseEstimator, WithoutDvlAndAttitudeRhoIsNaN) {
  sim::Sequence seq = fresh_sequence(60);
  seq.attitude.clear();
  seq.dvl.clear();
  testing::LogCapture log(LogLevel::kWarning);
  auto cfg = estimator_config(12.0);
  cfg.has_attitude = false;
  cfg.has_dvl = false;
  GlobalPoseEstimator est(cfg);
  std::vector<double> r_m, z_m, psi_r_rad;
  int64_t t_lock_ns = 0;
  int unaided_with_rho = 0;
  sim::Visitor v;
  v.depth = [&](const PressureSample& s) { est.add(s); };
  v.camera = [&](const NetObservation& obs, const sim::Pose& truth) {
    est.add(obs);
    const GlobalPose g = est.estimate(obs.t_ns);
    if (!std::isfinite(g.r_g_m)) return;
    if (r_m.empty()) t_lock_ns = obs.t_ns;
    const bool unaided = seconds_between(t_lock_ns, obs.t_ns) > cfg.max_unaided_s;
    if (unaided && (std::isfinite(g.rho_g_rad) || std::isfinite(g.psi_g_rad))) ++unaided_with_rho;
    r_m.push_back(std::abs(g.r_g_m - truth.r_m()));
    if (std::isfinite(g.z_g_m)) z_m.push_back(std::abs(g.z_g_m - truth.p_pen.z()));
    psi_r_rad.push_back(std::abs(wrap_angle(g.psi_r_rad - truth.psi_r_rad())));
  };
  sim::replay(seq, v);
  EXPECT_EQ(unaided_with_rho, 0);
  EXPECT_GE(r_m.size() + 5, seq.camera.size());
  EXPECT_GE(z_m.size() + 1, r_m.size());  // NaN only at a lock before the first depth sample
  EXPECT_LE(sim::median(r_m), 0.03);
  EXPECT_LE(sim::percentile(r_m, 0.95), 0.08);
  EXPECT_LE(sim::percentile(z_m, 0.99), 3 * sim::SensorNoise{}.depth_sigma_m);
  EXPECT_LE(sim::median(psi_r_rad) / kDeg, 1.5);
}

TEST(GlobalPoseEstimator, WithoutPressureDepthIsNaN) {
  sim::Sequence seq = fresh_sequence(20);
  seq.depth.clear();
  testing::LogCapture log(LogLevel::kWarning);
  auto cfg = estimator_config(12.0);
  cfg.has_pressure = false;
  GlobalPoseEstimator est(cfg);
  const Errors e = run_estimator(seq, est);
  EXPECT_NE(log.text().find("no pressure"), std::string::npos) << log.text();
  EXPECT_TRUE(e.z_m.empty());  // every z_g was NaN
  expect_locked_quickly(e);    // the other values were all produced
  EXPECT_LE(sim::median(e.r_m), 0.03);
}

bool all_nan(const Eigen::Isometry3d& T) {
  return T.matrix().array().isNaN().all();
}

// The rotation's yaw, pitch and roll (R = Rz(yaw) Ry(pitch) Rx(roll), |pitch| < 90 deg).
Eigen::Vector3d yaw_pitch_roll(const Eigen::Matrix3d& R) {
  return {std::atan2(R(1, 0), R(0, 0)), -std::asin(R(2, 0)), std::atan2(R(2, 1), R(2, 2))};
}

// The 6-DoF pose is the estimate itself: translation (r_g cos rho_g, r_g sin rho_g, z_g), yaw
// psi_g, roll and pitch the attitude sensor's at the frame time (interpolated as the estimator
// levels its sensors, AttitudeSeries), and T_pen_camera adds cam0's T_body_camera. Both are
// rounding away from these (1e-9). The first frames see no net: before the lock both poses are all
// NaN. Without a pressure sensor z_g is NaN and so are the poses.
TEST(GlobalPoseEstimator, BodyAndCameraPoseInThePen) {
  sim::Trajectory traj;
  traj.duration_s = 6;
  traj.roll_pitch_amp_rad = 6 * kDeg;
  std::mt19937_64 rng(testing::fresh_seed());
  sim::Sequence seq = sim::make_sequence(traj, {}, rng());
  const size_t blind = 3;
  for (size_t i = 0; i < blind; ++i) {
    seq.camera[i].points_C.clear();
    seq.camera[i].quality.clear();
  }
  GlobalPoseEstimator est(estimator_config(12.0));
  AttitudeSeries attitude;
  int before_lock = 0, with_pose = 0;
  double max_abs_roll = 0, max_abs_pitch = 0;
  sim::Visitor v;
  v.dvl = [&](const DvlSample& s) { est.add(s); };
  v.depth = [&](const PressureSample& s) { est.add(s); };
  v.attitude = [&](const AttitudeSample& s) {
    est.add(s);
    attitude.insert(s);
  };
  v.camera = [&](const NetObservation& obs, const sim::Pose&) {
    est.add(obs);
    const GlobalPose g = est.estimate(obs.t_ns);
    if (!est.initialised()) {
      ++before_lock;
      EXPECT_TRUE(all_nan(g.T_pen_body) && all_nan(g.T_pen_camera)) << obs.t_ns;
      return;
    }
    ASSERT_TRUE(std::isfinite(g.r_g_m) && std::isfinite(g.rho_g_rad) && std::isfinite(g.z_g_m) &&
                std::isfinite(g.psi_g_rad));
    ++with_pose;
    const Eigen::Vector3d p = g.T_pen_body.translation();
    EXPECT_NEAR(p.x(), g.r_g_m * std::cos(g.rho_g_rad), 1e-9);
    EXPECT_NEAR(p.y(), g.r_g_m * std::sin(g.rho_g_rad), 1e-9);
    EXPECT_NEAR(p.z(), g.z_g_m, 1e-9);
    const Eigen::Matrix3d R = g.T_pen_body.linear();
    EXPECT_TRUE((R.transpose() * R).isIdentity(1e-12));
    const Eigen::Vector3d ypr = yaw_pitch_roll(R);
    const auto a = attitude.at(obs.t_ns, est.config().max_attitude_gap_s);
    ASSERT_TRUE(a.has_value());
    EXPECT_NEAR(wrap_angle(ypr[0] - g.psi_g_rad), 0, 1e-9);
    EXPECT_NEAR(ypr[1], a->pitch_rad, 1e-9);
    EXPECT_NEAR(ypr[2], a->roll_rad, 1e-9);
    max_abs_pitch = std::max(max_abs_pitch, std::abs(ypr[1]));
    max_abs_roll = std::max(max_abs_roll, std::abs(ypr[2]));
    EXPECT_TRUE(
        g.T_pen_camera.matrix().isApprox((g.T_pen_body * sim::forward_camera()).matrix(), 1e-12));
    EXPECT_EQ(g.T_pen_camera.matrix().row(3), Eigen::RowVector4d(0, 0, 0, 1));
  };
  sim::replay(seq, v);
  EXPECT_GE(before_lock, static_cast<int>(blind));
  EXPECT_GE(with_pose + before_lock + 5, static_cast<int>(seq.camera.size()));
  // Not a comparison of zeros: the vehicle rolls and pitches by several degrees.
  EXPECT_GT(max_abs_roll, 2 * kDeg);
  EXPECT_GT(max_abs_pitch, 2 * kDeg);

  seq.depth.clear();
  auto no_depth = estimator_config(12.0);
  no_depth.has_pressure = false;
  testing::LogCapture log(LogLevel::kWarning);
  GlobalPoseEstimator est_no_depth(no_depth);
  int with_r_g = 0, with_finite_pose = 0;
  v.depth = nullptr;
  v.dvl = [&](const DvlSample& s) { est_no_depth.add(s); };
  v.attitude = [&](const AttitudeSample& s) { est_no_depth.add(s); };
  v.camera = [&](const NetObservation& obs, const sim::Pose&) {
    est_no_depth.add(obs);
    const GlobalPose g = est_no_depth.estimate(obs.t_ns);
    with_r_g += std::isfinite(g.r_g_m) && std::isfinite(g.rho_g_rad);
    with_finite_pose += !all_nan(g.T_pen_body) || !all_nan(g.T_pen_camera);
  };
  sim::replay(seq, v);
  EXPECT_GT(with_r_g, 0);
  EXPECT_EQ(with_finite_pose, 0);
}

// The published baseline's pose: its own r_g, rho_g, z_g, psi_g with the latest attitude
// sample's roll and pitch (even though its fix assumes them 0), NaN until it has all four.
TEST(PublishedGlobalPose, BodyAndCameraPoseInThePen) {
  sim::Trajectory traj;
  traj.duration_s = 3;
  traj.roll_pitch_amp_rad = 6 * kDeg;
  std::mt19937_64 rng(testing::fresh_seed());
  const sim::Sequence seq = sim::make_sequence(traj, {}, rng());
  PublishedGlobalPoseConfig cfg;
  cfg.T_body_camera = sim::forward_camera();
  PublishedGlobalPose node(cfg);
  AttitudeSample latest{.timestamp_ns = 0, .roll_rad = 0, .pitch_rad = 0, .yaw_rad = 0};
  int with_pose = 0;
  sim::Visitor v;
  v.dvl = [&](const DvlSample& s) { node.add(s); };
  v.depth = [&](const PressureSample& s) { node.add(s); };
  v.attitude = [&](const AttitudeSample& s) {
    node.add(s);
    latest = s;
  };
  v.camera = [&](const NetObservation& obs, const sim::Pose&) {
    const GlobalPose g = node.add(obs);
    if (!std::isfinite(g.r_g_m) || !std::isfinite(g.rho_g_rad) || !std::isfinite(g.z_g_m)) {
      EXPECT_TRUE(all_nan(g.T_pen_body) && all_nan(g.T_pen_camera));
      return;
    }
    ++with_pose;
    const Eigen::Vector3d p = g.T_pen_body.translation();
    EXPECT_NEAR(p.x(), g.r_g_m * std::cos(g.rho_g_rad), 1e-9);
    EXPECT_NEAR(p.y(), g.r_g_m * std::sin(g.rho_g_rad), 1e-9);
    EXPECT_NEAR(p.z(), g.z_g_m, 1e-9);
    const Eigen::Vector3d ypr = yaw_pitch_roll(g.T_pen_body.linear());
    EXPECT_NEAR(wrap_angle(ypr[0] - g.psi_g_rad), 0, 1e-9);
    EXPECT_NEAR(ypr[1], latest.pitch_rad, 1e-9);
    EXPECT_NEAR(ypr[2], latest.roll_rad, 1e-9);
    EXPECT_TRUE(
        g.T_pen_camera.matrix().isApprox((g.T_pen_body * sim::forward_camera()).matrix(), 1e-12));
  };
  sim::replay(seq, v);
  EXPECT_GE(with_pose + 5, static_cast<int>(seq.camera.size()));
  EXPECT_GT(latest.timestamp_ns, 0);
}

// Samples arriving up to 0.3 s late and out of order, plus duplicates, give the same estimates
// as the ordered stream; they are counted, and a sample older than the window is dropped.
// Late samples can hold what the ordered stream lacked at the same instant (an attitude sample
// after a camera frame lets roll and pitch be interpolated), so a first fix at the 4 cm residual
// limit may lock a frame apart, or the heading start from another yaw sample: over 4300 seeds
// rho_g and psi_g differed by 0.03 mrad typically, 0.6 mrad at the 99.9th percentile and 5.5 mrad
// at worst (3 seeds over 2 mrad).
TEST(GlobalPoseEstimator, OutOfOrderAndDuplicateSamples) {
  std::mt19937_64 rng(testing::fresh_seed());
  sim::Trajectory traj;
  traj.duration_s = 40;
  const sim::Sequence seq = sim::make_sequence(traj, {}, rng());
  GlobalPoseEstimator ordered(estimator_config(12.0));
  const Errors e_ordered = run_estimator(seq, ordered);

  // Arrival = timestamp + random latency; the camera frame's estimate is asked on its arrival.
  struct Arrival {
    double at_s;
    int kind;
    size_t index;
  };
  std::vector<Arrival> arrivals;
  std::uniform_real_distribution<double> latency(0.0, 0.3);
  auto t_of = [](int64_t t_ns) { return seconds_between(sim::kStart_ns, t_ns); };
  for (size_t i = 0; i < seq.dvl.size(); ++i)
    arrivals.push_back({t_of(seq.dvl[i].timestamp_ns) + latency(rng), 0, i});
  for (size_t i = 0; i < seq.depth.size(); ++i)
    arrivals.push_back({t_of(seq.depth[i].timestamp_ns) + latency(rng), 1, i});
  for (size_t i = 0; i < seq.attitude.size(); ++i)
    arrivals.push_back({t_of(seq.attitude[i].timestamp_ns) + latency(rng), 2, i});
  for (size_t i = 0; i < seq.camera.size(); ++i)
    arrivals.push_back({t_of(seq.camera[i].t_ns) + latency(rng), 3, i});
  std::sort(arrivals.begin(), arrivals.end(),
            [](const Arrival& a, const Arrival& b) { return a.at_s < b.at_s; });
  GlobalPoseEstimator shuffled(estimator_config(12.0));
  int duplicates = 0;
  for (const auto& a : arrivals) {
    const bool dup = a.index % 17 == 5;
    switch (a.kind) {
      case 0:
        shuffled.add(seq.dvl[a.index]);
        if (dup) shuffled.add(seq.dvl[a.index]);
        break;
      case 1:
        shuffled.add(seq.depth[a.index]);
        if (dup) shuffled.add(seq.depth[a.index]);
        break;
      case 2:
        shuffled.add(seq.attitude[a.index]);
        if (dup) shuffled.add(seq.attitude[a.index]);
        break;
      default:
        shuffled.add(seq.camera[a.index]);
        if (dup) shuffled.add(seq.camera[a.index]);
        (void)shuffled.estimate(seq.camera[a.index].t_ns);
    }
    duplicates += dup ? 1 : 0;
  }
  const int64_t t_end = seq.camera.back().t_ns;
  const GlobalPose a = ordered.estimate(t_end), b = shuffled.estimate(t_end);
  EXPECT_NEAR(a.r_g_m, b.r_g_m, 0.005);
  EXPECT_NEAR(a.rho_g_rad, b.rho_g_rad, 0.01);
  EXPECT_NEAR(a.psi_g_rad, b.psi_g_rad, 0.01);
  EXPECT_NEAR(a.z_g_m, b.z_g_m, 0.005);
  const auto c = shuffled.counters();
  EXPECT_EQ(c.dvl_velocity.duplicates + c.depth.duplicates + c.attitude.duplicates +
                c.vision_fix.duplicates,
            duplicates);
  EXPECT_GT(c.dvl_velocity.out_of_order + c.depth.out_of_order + c.attitude.out_of_order +
                c.vision_fix.out_of_order,
            100);
  EXPECT_EQ(
      c.dvl_velocity.too_late + c.depth.too_late + c.attitude.too_late + c.vision_fix.too_late, 0);
  EXPECT_NE(describe(c).find("out of order"), std::string::npos);
  // Far older than the 2 s window: dropped and counted, not fatal.
  shuffled.add(PressureSample{t_end - 10'000'000'000, 3.0});
  EXPECT_EQ(shuffled.counters().depth.too_late, 1);
  EXPECT_NEAR(shuffled.estimate(t_end).z_g_m, b.z_g_m, 1e-12);
  (void)e_ordered;
}

// Every sensor's counters count, including the DVL plane and the vision d_net / psi_net, which
// ride on the DVL and camera samples.
TEST(GlobalPoseEstimator, CountersCountEverySensor) {
  const sim::Sequence seq = fresh_sequence(10);
  GlobalPoseEstimator est(estimator_config(12.0));
  run_estimator(seq, est);
  const GlobalPoseCounters c = est.counters();
  std::printf("%s", describe(c).c_str());
  const std::pair<const char*, const SensorCounters*> rows[] = {
      {"DVL velocity", &c.dvl_velocity},
      {"DVL plane", &c.dvl_plane},
      {"depth", &c.depth},
      {"attitude", &c.attitude},
      {"vision fix", &c.vision_fix},
      {"vision d_net/psi_net", &c.vision_relative}};
  for (const auto& [name, n] : rows) {
    SCOPED_TRACE(name);
    EXPECT_GT(n->received, 0);
    EXPECT_GT(n->accepted, 0);
    EXPECT_EQ(n->received, n->accepted + n->rejected + n->invalid + n->not_lockable);
  }
  EXPECT_EQ(c.dvl_velocity.received, static_cast<int>(seq.dvl.size()));
  EXPECT_EQ(c.vision_fix.received, static_cast<int>(seq.camera.size()));
  // Each camera frame carries d_net / psi_net; the frames before and at the lock do not count.
  EXPECT_EQ(c.vision_relative.received,
            static_cast<int>(seq.camera.size()) - 1 - c.vision_fix.not_lockable);
  EXPECT_NE(
      describe(c).find("DVL plane             received " + std::to_string(c.dvl_plane.received)),
      std::string::npos);
}

// Keeps only the ROIs of the last `columns` grid columns (5 x 6 grid, row-major): the net
// entering the view from the side.
void keep_columns(NetObservation& obs, int columns) {
  for (size_t i = 0; i < obs.points_C.size(); ++i)
    if (static_cast<int>(i % 6) < 6 - columns) obs.points_C[i].setConstant(kNaN);
}

// The first frames see the net only in two columns of ROIs, with their points 1 m too far (a
// partial net fitted to a wrong circle): the lock rule refuses them, the filter starts on the
// first full view and is accurate from there.
TEST(GlobalPoseEstimator, PartialNetFixDoesNotInitialise) {
  sim::Sequence seq = fresh_sequence(10);
  const size_t partial = 10;
  for (size_t i = 0; i < partial; ++i) {
    keep_columns(seq.camera[i], 2);
    for (auto& p : seq.camera[i].points_C) p *= (p.norm() + 1.0) / p.norm();
  }
  GlobalPoseEstimator est(estimator_config(12.0));
  const Errors e = run_estimator(seq, est);
  const GlobalPoseCounters c = est.counters();
  EXPECT_GE(c.vision_fix.not_lockable, static_cast<int>(partial));
  EXPECT_EQ(e.frames_before_lock, c.vision_fix.not_lockable);
  expect_locked_quickly(e, static_cast<int>(partial));
  EXPECT_LE(*std::max_element(e.r_m.begin(), e.r_m.end()), 0.05);
  // Without the rule the first partial fix starts the filter 1 m off.
  GlobalPoseEstimatorConfig no_rule = estimator_config(12.0);
  no_rule.lock.min_inliers = 3;
  no_rule.lock.min_bearing_spread_rad = 0;
  no_rule.lock.max_r_sigma_m = 1e9;
  no_rule.lock.max_residual_rms_m = 1e9;
  no_rule.lock.reinit_after_rejected_fixes = 0;
  no_rule.use_dvl_plane = false;  // its check would refuse the wrong circle too
  GlobalPoseEstimator naive(no_rule);
  const Errors n = run_estimator(seq, naive);
  EXPECT_GT(n.r_m.front(), 0.5);
}

// The FFT pose's quality scales its weight (core/pose_trust.h): a d_net reading 8 % long on every
// frame pulls r_g much less when its quality says the pose is weak (trust 0.1: ten times the
// variance) than when it says it is a whole frontal net.
TEST(GlobalPoseEstimator, AWeakFftPosePullsLess) {
  const sim::Sequence seq = fresh_sequence(20);
  const auto median_r_error = [&](double d_net_scale, double quality) {
    sim::Sequence s = seq;
    for (NetObservation& obs : s.camera) {
      obs.d_net_m *= d_net_scale;
      obs.pose_quality = quality;
    }
    GlobalPoseEstimator est(estimator_config(12.0));
    return sim::median(run_estimator(s, est).r_m);
  };
  const double unbiased = median_r_error(1.0, 1.0);
  const double strong = median_r_error(1.08, 1.0) - unbiased;
  const double weak = median_r_error(1.08, 0.05) - unbiased;
  std::printf("r_g error added by d_net 8 %% long: median %.4f m at quality 1, %.4f m at 0.05\n",
              strong, weak);
  EXPECT_GT(strong, 0.002);  // 3.6 mm and more on 60 seeds; weak at most 0.4 mm
  EXPECT_LT(weak, 0.3 * strong);
}

// Frames 1-3 have all points moved 1.5 m along the optical axis (frame 0 sees nothing): a full,
// self-consistent, wrong circle that passes the fix-only rule. Without the DVL plane to contradict
// it the filter starts there, gates the good fixes out, and after reinit_after_rejected_fixes
// agreeing ones re-locks its position (counted, logged) and is accurate again.
TEST(GlobalPoseEstimator, AgreeingRejectedFixesReinitialise) {
  sim::Sequence seq = fresh_sequence(10);
  const size_t bad_end = 4;
  for (auto& p : seq.camera[0].points_C) p.setConstant(kNaN);
  for (size_t i = 1; i < bad_end; ++i) {
    for (auto& p : seq.camera[i].points_C) p.z() += 1.5;
  }
  GlobalPoseEstimatorConfig cfg = estimator_config(12.0);
  cfg.use_dvl_plane = false;
  cfg.use_vision_relative = false;
  testing::LogCapture log(LogLevel::kWarning);
  GlobalPoseEstimator est(cfg);
  const Errors e = run_estimator(seq, est);
  const GlobalPoseCounters c = est.counters();
  EXPECT_EQ(c.vision_fix.reinitialised, 1);
  EXPECT_NE(log.text().find("re-initialised"), std::string::npos);
  EXPECT_GT(e.r_m.front(), 1.0);
  // Re-locked within reinit_after_rejected_fixes + 2 frames (0.1 s each) of the last bad one,
  // plus up to 3 frames: a good fix refused by the lock rule (an outlier ROI among the inliers,
  // ~0.5 % of frames) restarts the run of agreeing fixes (1 seed in ~3000 needed one more frame).
  const double t_locked =
      0.1 *
      static_cast<double>(bad_end + 5 + static_cast<size_t>(cfg.lock.reinit_after_rejected_fixes));
  std::vector<double> r_after, psi_after;
  for (size_t i = 0; i < e.t_s.size(); ++i) {
    if (e.t_s[i] < t_locked - 1e-6) continue;
    r_after.push_back(e.r_m[i]);
    psi_after.push_back(e.psi_rad[i]);
  }
  ASSERT_FALSE(r_after.empty());
  const double worst_after = *std::max_element(r_after.begin(), r_after.end());
  std::printf("wrong start: r_g error %.2f m at first, <= %.4f m from %.1f s on\n", e.r_m.front(),
              worst_after, t_locked);
  EXPECT_LE(worst_after, 0.05);
  EXPECT_LE(sim::median(psi_after) / kDeg, 1.5);
  // The same wrong start is refused by the DVL plane check when the plane is on.
  GlobalPoseEstimator with_plane(estimator_config(12.0));
  const Errors p = run_estimator(seq, with_plane);
  EXPECT_GE(with_plane.counters().vision_fix.not_lockable, static_cast<int>(bad_end - 1));
  expect_locked_quickly(p, static_cast<int>(bad_end));
  EXPECT_LE(p.r_m.front(), 0.05);
  EXPECT_EQ(with_plane.counters().vision_fix.reinitialised, 0);
}

TEST(GlobalPoseEstimator, BadConfigurationAndInputAreErrors) {
  GlobalPoseEstimatorConfig cfg;
  cfg.pen_radius_m = 0;
  EXPECT_THROW(GlobalPoseEstimator{cfg}, pensight::Error);
  cfg.pen_radius_m = kNaN;
  EXPECT_THROW(GlobalPoseEstimator{cfg}, pensight::Error);
  GlobalPoseEstimator est(estimator_config(12.0));
  NetObservation obs;
  obs.points_C.assign(30, Eigen::Vector3d(0, 0, 1));
  obs.quality.assign(29, 1.0);
  EXPECT_THROW(est.add(obs), pensight::Error);
  // A frame without usable points is not an error: no fix, NaN, counted.
  obs.quality.clear();
  obs.points_C.assign(30, Eigen::Vector3d::Constant(kNaN));
  est.add(obs);
  const GlobalPose g = est.estimate(obs.t_ns);
  EXPECT_TRUE(std::isnan(g.r_g_m));
  EXPECT_EQ(est.counters().vision_fix.invalid, 1);
}

}  // namespace
}  // namespace pensight::global_pose
