// The whole chain on rendered sequences: scenario -> CPU reference renderer -> dataset ->
// `pensight run` (FFT detector on the CPU + fused global pose) -> scored against the truth.
// Short cuts (3.5 s, 36 frames, 1 sample per pixel) of the 12 m pen, a 25 m pen and the flat
// tank, the camera 0.5-1.1 m from the net. Bounds are the acceptance: r_g median <= 3 cm,
// p95 <= 8 cm; psi_g change median <= 1.5 deg; z_g within the pressure sensor's bias plus 3 sigma
// of its noise (the bias is a constant offset no estimator can see).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pipeline/evaluation/evaluation.h"
#include "tests/support/rendered_run.h"

namespace pensight {
namespace {

constexpr double kDurationS = 3.5;

sim::Scenario scenario(const std::string& file, double pen_radius_m = 0) {
  sim::Scenario s = testing::shipped_scenario(file, kDurationS);
  if (pen_radius_m > 0) s.pen.radius_m = pen_radius_m;
  sim::validate(s);
  return s;
}

// Renders, runs and scores; checks the acceptance bounds.
void check(const sim::Scenario& s) {
  const testing::RenderedRun run = testing::render_and_run(s);
  const GlobalPoseAccuracy a = score_global_pose(run.dataset, run.rows);
  ::testing::Test::RecordProperty("accuracy", describe(a));
  std::printf("%s, R = %.0f m:\n%sestimator counters:\n%s\n", s.name.c_str(), s.pen.radius_m,
              describe(a).c_str(), run.summary.global_pose_counters.c_str());

  ASSERT_EQ(a.frames, static_cast<size_t>(s.num_frames()));
  // The first frame with a net fix starts everything; allow the first two to go without.
  EXPECT_GE(a.with_r_g + 2, a.frames);
  EXPECT_GE(a.with_rho_psi + 2, a.frames);
  EXPECT_EQ(a.with_z_g, a.frames);
  EXPECT_LE(a.r_g_m.median, 0.03);
  EXPECT_LE(a.r_g_m.p95, 0.08);
  EXPECT_LE(a.psi_change_deg.median, 1.5);
  EXPECT_LE(a.z_g_m.max, std::abs(s.pressure.bias_m) + 3 * s.pressure.noise_m);
}

TEST(GlobalPoseRendered, Pen12m) {
  check(scenario("follow.yaml"));
}

TEST(GlobalPoseRendered, Pen25m) {
  check(scenario("follow.yaml", 25.0));
}

// The tank's net is the plane x = 100 m (sim/scenario.h), and scene.yaml gives radius 100: the
// estimator fits a 100 m circle to a flat net. Against the cylinder truth hypot(x, y) that costs
// y^2 / 2x (7 mm at the start, 1.2 m along), and rho changes by atan(y / x).
TEST(GlobalPoseRendered, FlatTank) {
  check(scenario("tank.yaml"));
}

}  // namespace
}  // namespace pensight
