#include "pipeline/global_pose/pen_fix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "tests/pipeline/global_pose/pen_sim.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::global_pose {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A random pose 0.5-2 m (body origin) from the wall, facing it within +-25 deg.
sim::Pose random_pose(double radius, std::mt19937_64& rng, double roll_pitch_amp = 0) {
  std::uniform_real_distribution<double> dist(0.5, 2.0), yaw(-25 * kDeg, 25 * kDeg), rho(-3.1, 3.1),
      depth(2.0, 10.0), rp(-roll_pitch_amp, roll_pitch_amp);
  sim::Pose p;
  const double r = radius - dist(rng), a = rho(rng);
  p.p_pen = Eigen::Vector3d(r * std::cos(a), r * std::sin(a), depth(rng));
  p.yaw_rad = wrap_angle(a + yaw(rng));
  p.roll_rad = rp(rng);
  p.pitch_rad = rp(rng);
  return p;
}

TEST(CircleFit, ExactArcWithGrossOutliersIsRecovered) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0, 100.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::uniform_real_distribution<double> u(-1, 1);
      // Observer (origin) 0.5-2 m inside the wall, which is seen around bearing a0.
      const double a0 = u(rng) * 0.3, dist = 1.25 + 0.75 * u(rng);
      const Eigen::Vector2d centre = -(radius - dist) * Eigen::Vector2d(std::cos(a0), std::sin(a0));
      const double span = 2.0 / radius;  // about 2 m of wall
      std::vector<Eigen::Vector2d> pts;
      for (int i = 0; i < 30; ++i) {
        const double a = a0 + span * (i / 29.0 - 0.5);
        const Eigen::Vector2d radial(std::cos(a), std::sin(a));
        Eigen::Vector2d p = centre + radius * radial;
        // Every 4th point is a gross outlier 0.3-1.3 m off the wall, either side.
        if (i % 4 == 1) p += (i % 8 == 1 ? -1 : 1) * (0.3 + std::abs(u(rng))) * radial;
        pts.push_back(p);
      }
      pts.push_back(Eigen::Vector2d::Constant(kNaN));  // skipped, not fatal
      CircleFitOptions o;
      o.radius_m = radius;
      const CircleFit fit = fit_circle_known_radius(pts, o);
      ASSERT_TRUE(fit.ok);
      const PenFix fix = pen_fix_from_circle(fit);
      EXPECT_NEAR(fix.r_g_m, centre.norm(), 1e-6) << "R = " << radius;
      EXPECT_NEAR(fix.psi_r_rad, -std::atan2(-centre.y(), -centre.x()), 1e-6);
      EXPECT_LT(fit.residual_rms_m, 1e-6);
      EXPECT_LE(fit.inliers, 30 - 5);  // the displaced points are not inliers
    }
  }
}

TEST(CircleFit, TooFewPointsGiveNaN) {
  CircleFitOptions o;
  const std::vector<Eigen::Vector2d> two = {{11, 0}, {11, 0.5}};
  const CircleFit fit = fit_circle_known_radius(two, o);
  EXPECT_FALSE(fit.ok);
  const std::vector<double> one_weight = {1.0};
  EXPECT_THROW(fit_circle_known_radius(two, o, one_weight), pensight::Error);
  const PenFix fix = pen_fix_from_circle(fit);
  EXPECT_FALSE(fix.ok);
  EXPECT_TRUE(std::isnan(fix.r_g_m));
  EXPECT_TRUE(std::isnan(fix.psi_r_rad));
}

struct FixErrors {
  std::vector<double> r_m, psi_rad;
};

FixErrors fix_errors(double radius, double roll_pitch_amp, bool level_with_attitude,
                     std::mt19937_64& rng, int poses = 300) {
  FixErrors e;
  CircleFitOptions o;
  o.radius_m = radius;
  const auto T_bc = sim::forward_camera();
  for (int i = 0; i < poses; ++i) {
    const sim::Pose pose = random_pose(radius, rng, roll_pitch_amp);
    const NetObservation obs = sim::net_observation(pose, radius, T_bc, {}, rng);
    const PenFix fix =
        pen_fix_from_net_points(obs.points_C, T_bc, level_with_attitude ? pose.roll_rad : 0.0,
                                level_with_attitude ? pose.pitch_rad : 0.0, o, obs.quality);
    EXPECT_TRUE(fix.ok);
    if (!fix.ok) continue;
    e.r_m.push_back(std::abs(fix.r_g_m - pose.r_m()));
    e.psi_rad.push_back(std::abs(wrap_angle(fix.psi_r_rad - pose.psi_r_rad())));
  }
  return e;
}

// Published acceptance bounds at 0.5-2 m from the net, 1.5 % range noise + 10 % outliers.
TEST(PenFix, RadialDistanceAndRelativeYawWithinBounds) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0, 100.0}) {
    const FixErrors e = fix_errors(radius, 0.0, false, rng);
    const double med = sim::median(e.r_m), p95 = sim::percentile(e.r_m, 0.95);
    const double psi_med = sim::median(e.psi_rad) / kDeg;
    std::printf("R = %5.1f m: r_g error median %.4f m, p95 %.4f m; psi_r error median %.3f deg\n",
                radius, med, p95, psi_med);
    EXPECT_LE(med, 0.03) << "R = " << radius;
    EXPECT_LE(p95, 0.08) << "R = " << radius;
    EXPECT_LE(psi_med, 1.5) << "R = " << radius;
  }
}

// With +-10 deg of roll and pitch the attitude-levelled fix keeps the bounds; the published
// roll = pitch = 0 assumption does not do better.
TEST(PenFix, AttitudeLevellingHandlesRollAndPitch) {
  std::mt19937_64 rng(testing::fresh_seed());
  const double amp = 10 * kDeg;
  const uint64_t seed = rng();
  std::mt19937_64 rng_a(seed), rng_b(seed);
  const FixErrors levelled = fix_errors(12.0, amp, true, rng_a);
  const FixErrors assumed = fix_errors(12.0, amp, false, rng_b);
  std::printf("roll/pitch +-10 deg: r_g p95 %.4f m levelled, %.4f m assuming level\n",
              sim::percentile(levelled.r_m, 0.95), sim::percentile(assumed.r_m, 0.95));
  EXPECT_LE(sim::median(levelled.r_m), 0.03);
  EXPECT_LE(sim::percentile(levelled.r_m, 0.95), 0.08);
  EXPECT_LE(sim::median(levelled.psi_rad) / kDeg, 1.5);
  EXPECT_GT(sim::percentile(assumed.r_m, 0.95), sim::percentile(levelled.r_m, 0.95));
}

// The published node on a 2-minute pass along the wall.
TEST(PublishedGlobalPose, SequenceErrorsWithinBounds) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const double radius : {12.0, 25.0, 100.0}) {
    sim::Trajectory traj;
    traj.radius_m = radius;
    const sim::SensorNoise noise;
    const sim::Sequence seq = sim::make_sequence(traj, noise, rng());
    PublishedGlobalPoseConfig cfg;
    cfg.pen_radius_m = radius;
    cfg.T_body_camera = sim::forward_camera();
    PublishedGlobalPose node(cfg);
    std::vector<double> r_err, psi_err, psi_r_err, z_err;
    double rho0 = kNaN, psi0 = kNaN;
    sim::Visitor v;
    v.dvl = [&](const DvlSample& s) { node.add(s); };
    v.depth = [&](const PressureSample& s) { node.add(s); };
    v.camera = [&](const NetObservation& obs, const sim::Pose& truth) {
      const GlobalPose g = node.add(obs);
      ASSERT_TRUE(std::isfinite(g.r_g_m) && std::isfinite(g.rho_g_rad) &&
                  std::isfinite(g.psi_g_rad));
      if (!std::isfinite(g.z_g_m)) {  // no pressure sample before the first frame
        EXPECT_LT(truth.t_s, 0.05);
        return;
      }
      if (std::isnan(rho0)) {
        rho0 = truth.rho_rad() - g.rho_g_rad;
        psi0 = rho0;
      }
      r_err.push_back(std::abs(g.r_g_m - truth.r_m()));
      psi_err.push_back(std::abs(wrap_angle(g.psi_g_rad + psi0 - truth.yaw_rad)));
      psi_r_err.push_back(std::abs(wrap_angle(g.psi_r_rad - truth.psi_r_rad())));
      z_err.push_back(std::abs(g.z_g_m - truth.p_pen.z()));
    };
    sim::replay(seq, v);
    std::printf("published R = %5.1f: r_g median %.4f p95 %.4f m, psi_g median %.3f deg\n", radius,
                sim::median(r_err), sim::percentile(r_err, 0.95), sim::median(psi_err) / kDeg);
    EXPECT_LE(sim::median(r_err), 0.03);
    EXPECT_LE(sim::percentile(r_err, 0.95), 0.08);
    // psi_g carries the rho_g drift of DVL dead reckoning (1 % scale error here): reported, and
    // bounded in the estimator's test; the vision part psi_r meets the bound.
    EXPECT_LE(sim::median(psi_r_err) / kDeg, 1.5);
    // Pressure noise 2 cm plus up to one 8 Hz sample of depth change (about 1 cm).
    EXPECT_LE(sim::percentile(z_err, 0.99), 3 * noise.depth_sigma_m + 0.012);
  }
}

TEST(PublishedGlobalPose, WithoutDvlRhoAndPsiAreNaN) {
  PublishedGlobalPoseConfig cfg;
  cfg.T_body_camera = sim::forward_camera();
  cfg.has_dvl = false;
  PublishedGlobalPose node(cfg);
  std::mt19937_64 rng(testing::fresh_seed());
  const sim::Trajectory traj;
  const NetObservation obs = sim::net_observation(traj.at(0), 12.0, cfg.T_body_camera, {}, rng);
  node.add(DvlSample{obs.t_ns - 1, Eigen::Vector3d(0.1, 0.2, 0), true, {}});
  const GlobalPose g = node.add(obs);
  EXPECT_TRUE(std::isfinite(g.r_g_m));
  EXPECT_TRUE(std::isnan(g.rho_g_rad));
  EXPECT_TRUE(std::isnan(g.psi_g_rad));
}

}  // namespace
}  // namespace pensight::global_pose
