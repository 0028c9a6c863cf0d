// The whole chain on rendered sequences: scenario -> CPU reference renderer -> dataset ->
// `pensight run` (FFT detector on the CPU + fused global pose) -> scored against the truth.
// - Short cuts (3.5 s, 36 frames, 1 sample per pixel) of the 12 m pen, a 25 m pen and the flat
//   tank, the camera 0.5-1.1 m from the net. Bounds are the acceptance: r_g median
//   <= 3 cm, p95 <= 8 cm; psi_g change median <= 1.5 deg; z_g within the pressure sensor's bias
//   plus 3 sigma of its noise (the bias is a constant offset no estimator can see).
// - The whole sweep (6 s): it starts facing open water, so the first fixes see a partial net.
// - follow_drift.yaml (30 s at 2 Hz): rho_g drift per metre of the estimator against the
//   published node on the same run, and recovery from an injected DVL spike.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/units.h"
#include "tests/support/rendered_run.h"
#include "tests/support/test_seed.h"
#include "tools/evaluation/evaluation.h"

namespace pensight {
namespace {

constexpr double kDuration_s = 3.5;
// oblique.yaml, seeds 1-20: r_g from frame 0 on every frame, error max 14-33 mm.
constexpr size_t kMaxObliqueFirstFrame = 5;
constexpr double kMaxObliqueRgError_m = 0.1;

sim::Scenario scenario(const std::string& file, double pen_radius_m = 0) {
  sim::Scenario s = testing::shipped_scenario(file, kDuration_s);
  if (pen_radius_m > 0) s.pen.radius_m = pen_radius_m;
  sim::validate(s);
  return s;
}

// Renders, runs and scores; checks the acceptance bounds and hands the scores to `scores`.
void check(const sim::Scenario& s, GlobalPoseAccuracy* scores = nullptr) {
  const testing::RenderedRun run = testing::render_and_run(s);
  const GlobalPoseAccuracy a = score_global_pose(run.dataset, run.rows);
  if (scores) *scores = a;
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

// The tank's net is a flat panel (scene.yaml net_type: flat_panel, the plane x = 100 m): the
// estimator models the plane, so psi_g does not turn with the position along it as a 100 m
// cylinder's normal would (1.4 deg over the run's 2.4 m). Issue bound: 0.2 deg drift.
TEST(GlobalPoseRendered, FlatTank) {
  GlobalPoseAccuracy a;
  check(scenario("tank.yaml"), &a);
  EXPECT_LE(a.psi_change_deg.max, 0.2);
}

// Looking along the net 31-51 deg off its normal (scenarios/oblique.yaml, 6 s): the circle fit of
// such frames is not trusted alone, but the DVL's net plane, measured by its beams apart from the
// ROIs, confirms it, so the filter starts on the first frames and follows the truth.
TEST(GlobalPoseRendered, ObliqueViewsStartWithTheDvlPlanesConfirmation) {
  sim::Scenario s = testing::shipped_scenario("oblique.yaml");
  s.seed = testing::fresh_seed();
  const testing::RenderedRun run = testing::render_and_run(s);
  std::vector<double> r_err;
  size_t first = run.rows.size();
  for (size_t i = 0; i < run.rows.size(); ++i) {
    const GroundTruthRow* t = run.dataset.truth_for_frame(i);
    ASSERT_NE(t, nullptr);
    if (!std::isfinite(run.rows[i].r_g_m)) continue;
    first = std::min(first, i);
    r_err.push_back(run.rows[i].r_g_m - t->p_pen_body_m.head<2>().norm());
  }
  const ErrorStats e = error_stats(r_err);
  std::printf(
      "oblique: r_g from frame %zu, on %zu of %zu frames: error median %.1f mm, p95 %.1f "
      "mm, max %.1f mm\n",
      first, r_err.size(), run.rows.size(), 1e3 * e.median, 1e3 * e.p95, 1e3 * e.max);
  EXPECT_LE(first, kMaxObliqueFirstFrame);
  EXPECT_LE(e.max, kMaxObliqueRgError_m);
}

// The sweep turns from open water to the net and away again. The first fixes come from the few
// ROIs at the image edge that see the net entering; the lock rule keeps them from starting the
// filter. Scored over the frames where the net fills at least half the image (the issue's
// envelope, whatever the distance).
TEST(GlobalPoseRendered, SweepFromOpenWater) {
  const sim::Scenario s = testing::shipped_scenario("sweep.yaml");
  const testing::RenderedRun run = testing::render_and_run(s);
  std::vector<double> r_err, r_err_envelope;
  size_t full_view = 0, envelope = 0, envelope_without = 0;
  const AccuracyEnvelope env;
  for (size_t i = 0; i < run.rows.size(); ++i) {
    const GroundTruthRow* t = run.dataset.truth_for_frame(i);
    ASSERT_NE(t, nullptr);
    if (t->net_fraction < env.min_net_fraction) continue;
    ++full_view;
    // The envelope: also 0.4-2.5 m from the net and facing it within 35 deg (not the far
    // wall 3-12 m away, nor the net seen obliquely while turning in and out).
    const bool in_envelope = t->d_net_m >= env.min_d_net_m && t->d_net_m <= env.max_d_net_m &&
                             std::abs(t->psi_net_rad) <= env.max_abs_psi_net_rad;
    envelope += in_envelope ? 1 : 0;
    const double r_true = t->p_pen_body_m.head<2>().norm();
    if (!std::isfinite(run.rows[i].r_g_m)) {
      envelope_without += in_envelope ? 1 : 0;
      continue;
    }
    r_err.push_back(run.rows[i].r_g_m - r_true);
    if (in_envelope) r_err_envelope.push_back(r_err.back());
  }
  const ErrorStats e = error_stats(r_err), ee = error_stats(r_err_envelope);
  std::printf(
      "sweep: %zu frames with net >= half the image, %zu with r_g: r_g error median %.1f mm, "
      "p95 %.1f mm, max %.1f mm\n  of them %zu in the envelope, %zu with r_g: median %.1f mm, "
      "p95 %.1f mm, max %.1f mm\nestimator counters:\n%s\n",
      full_view, r_err.size(), 1e3 * e.median, 1e3 * e.p95, 1e3 * e.max, envelope,
      r_err_envelope.size(), 1e3 * ee.median, 1e3 * ee.p95, 1e3 * ee.max,
      run.summary.global_pose_counters.c_str());
  ::testing::Test::RecordProperty("sweep_r_g_max_mm", std::to_string(1e3 * e.max));
  ASSERT_GE(full_view, 40u);
  ASSERT_GE(envelope, 30u);
  EXPECT_LE(envelope_without, 2u);  // the lock waits for |psi_r| <= 25 deg
  // The medians are the bulge: the net is up to 15 cm inside the cylinder there, and r_g is
  // measured to the net (the published node's median is the same). Measured 2026-11-22: median
  // 117 mm, p95 154 mm, max 158 mm, the same in the envelope. Before the lock rule: envelope p95
  // 4.2 m, max 5.0 m; with the lock rule and the old process noise (0.05): p95 0.44 m, max 1.0 m.
  EXPECT_LE(e.median, 0.15);
  EXPECT_LE(e.max, 0.25);
  EXPECT_LE(ee.median, 0.15);
  EXPECT_LE(ee.p95, 0.2);
}

// follow_drift.yaml, rendered once and run twice: as rendered (with its injected DVL spike) and
// with the spike taken out of the DVL samples in memory (the spike-free run; the sim adds the
// spike last, so subtracting it gives exactly the samples a spike-free scenario would).
// Drift (docs/global_pose.md: |mean arc error over the last 5 s| / path) on the spike-free run:
// the estimator at most half the published node's. Spike: 2 s after it the estimator is within
// 1 cm (r_g) and 2 cm of arc (rho_g) of the spike-free run, while the published rho_g jumps.
TEST(GlobalPoseRendered, DriftAndDvlSpikeRecovery) {
  const sim::Scenario s = testing::shipped_scenario("follow_drift.yaml");
  ASSERT_EQ(s.dvl.spikes.size(), 1u);
  const sim::DvlSpike& spike = s.dvl.spikes.front();
  const testing::RenderedDataset rendered(s);
  Dataset clean = rendered.dataset();
  ASSERT_TRUE(clean.dvl0.has_value());
  const int64_t spike_from = s.start_time_ns + seconds_to_ns_toward_zero(spike.t_s);
  const int64_t spike_to = spike_from + seconds_to_ns_toward_zero(spike.duration_s);
  int spiked_samples = 0;
  for (DvlSample& d : clean.dvl0->samples) {
    if (d.valid && d.timestamp_ns >= spike_from && d.timestamp_ns < spike_to) {
      d.velocity_B_mps -= spike.velocity_B_mps;
      ++spiked_samples;
    }
  }
  ASSERT_EQ(spiked_samples, 2);

  std::vector<EstimateRow> published_clean, published_spiked;
  const testing::RenderedRun est_clean = rendered.run(clean, "clean", &published_clean);
  const testing::RenderedRun est_spiked =
      rendered.run(rendered.dataset(), "spiked", &published_spiked);
  const GlobalPoseAccuracy e = score_global_pose(clean, est_clean.rows);
  const GlobalPoseAccuracy p = score_global_pose(clean, published_clean);
  std::printf(
      "spike-free run, estimator:\n%spublished node:\n%sestimator counters (spiked run):\n%s",
      describe(e).c_str(), describe(p).c_str(), est_spiked.summary.global_pose_counters.c_str());
  ::testing::Test::RecordProperty("drift_estimator_percent",
                                  std::to_string(100 * e.rho_drift_per_m));
  ::testing::Test::RecordProperty("drift_published_percent",
                                  std::to_string(100 * p.rho_drift_per_m));
  EXPECT_GE(e.path_m, 8.0);
  EXPECT_LE(e.rho_drift_per_m, 0.5 * p.rho_drift_per_m);
  // The acceptance bounds hold over the whole run too.
  EXPECT_LE(e.r_g_m.median, 0.03);
  EXPECT_LE(e.r_g_m.p95, 0.08);
  EXPECT_LE(e.psi_change_deg.median, 1.5);

  // Spiked vs spike-free, frame by frame: r_g and the arc r * rho_g.
  const auto differences = [&](const std::vector<EstimateRow>& a, const std::vector<EstimateRow>& b,
                               int64_t from, int64_t to) {
    double r_max = 0, arc_max = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
      if (a[i].timestamp_ns < from || a[i].timestamp_ns > to) continue;
      r_max = std::max(r_max, std::abs(a[i].r_g_m - b[i].r_g_m));
      arc_max = std::max(arc_max, std::abs(a[i].rho_g_rad - b[i].rho_g_rad) * b[i].r_g_m);
    }
    return std::pair{r_max, arc_max};
  };
  const int64_t end = clean.frames.back().timestamp_ns;
  const int64_t recovered = spike_from + 2'000'000'000;
  const auto [r_during, arc_during] =
      differences(est_spiked.rows, est_clean.rows, spike_from, recovered);
  const auto [r_after, arc_after] = differences(est_spiked.rows, est_clean.rows, recovered, end);
  const auto [pub_r_after, pub_arc_after] =
      differences(published_spiked, published_clean, recovered, end);
  std::printf(
      "DVL spike at %.1f s: estimator moved r_g %.1f mm / arc %.1f mm within 2 s, "
      "%.1f mm / %.1f mm after; published arc %.0f mm after\n",
      spike.t_s, 1e3 * r_during, 1e3 * arc_during, 1e3 * r_after, 1e3 * arc_after,
      1e3 * pub_arc_after);
  EXPECT_LE(r_after, 0.01);
  EXPECT_LE(arc_after, 0.02);
  EXPECT_GT(pub_arc_after, 0.5);  // the spike is real: the published node keeps ~1 m of it
  // Every row of the spiked run has a finite estimate (nothing dropped out around the spike).
  for (const EstimateRow& r : est_spiked.rows) {
    EXPECT_TRUE(std::isfinite(r.r_g_m) && std::isfinite(r.rho_g_rad));
  }
}

}  // namespace
}  // namespace pensight
