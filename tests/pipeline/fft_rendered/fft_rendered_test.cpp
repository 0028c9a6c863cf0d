// Issue 4's accuracy acceptance on the synthetic world's own renders: short sequences of the
// shipped scenarios (1 sample per pixel, CPU renderer), through `pensight run`'s pipeline on the
// CPU backend, scored by `pensight evaluate`'s code. Full-length numbers: docs/fft_detection.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "sim/frame_state.h"
#include "tests/support/rendered_run.h"
#include "tests/support/test_seed.h"
#include "tools/evaluation/evaluation.h"

namespace pensight {
namespace {

struct Case {
  const char* scenario;
  double duration_s;     // 0: the whole scenario
  size_t min_estimated;  // measurable frames with an estimate: no pass on a handful
};

// Measured over seeds 1-8 (docs/validation-log.md 2026-12-06), with a margin: ropes 117-119
// of 121 frames with a pose, none more than 20 % off, d_net median 0.17-0.28 %, p95 1.89-2.47 %
// (issue 37 asks 2 %: open), psi median 0.35-0.41 deg. Oblique frames over seeds 1-60
// (2026-12-07): all with a pose, d_net median 0.68-2.31 %, max 2.2-5.1 %. The changing net
// (2026-12-06): 65 of 65 frames with a pose, d_net median 0.11-0.14 %, p95 0.34-0.41 %, the
// changes' first frames at most 0.42 % off.
constexpr size_t kMinRopesEstimated = 110;
constexpr double kMaxRopesP95 = 0.03;
constexpr double kMaxObliqueMedian = 0.03, kMaxObliqueMax = 0.06;
// Seeds 1-40 (2026-12-07): 11 of 11 frames with a pose on every seed (4-10 before the ROIs'
// tilts were compared with the curved wall's normals), median <= 0.19 %, max <= 0.37 %. The fouled
// net beyond the planned grid's reach (2026-12-07), seeds 1-40: 11 of 11 frames on every seed,
// median <= 0.33 %, max <= 0.37 % (on the planned grid, 3 of seeds 1-6 read medians 0.5-0.9 %).
constexpr double kMinFarShare = 0.9, kMaxFarMedian = 0.005, kMaxFarMax = 0.01;
// The fold (2026-12-08), seeds 1-30: 113-116 of 121 frames with a pose, none more than 20 % off,
// d_net median 0.08-0.13 %, p95 0.77-1.98 % (one seed at 1.98, the rest at most 1.39), psi
// median 0.57-0.72 deg (issue 37 asks 0.5: open). With three panels in view (between the folds'
// feet) the pose is one plane through them, psi 4-8 deg off; at a fold line it can be the other
// panel's (26 deg off); the ridge's line in mid-view is refused for 0.7 s.
constexpr size_t kMinFoldEstimated = 108;
constexpr double kMaxFoldP95 = 0.03, kMaxFoldPsiMedian_deg = 1.0;
constexpr size_t kMinChangingEstimated = 63;
constexpr double kMaxChangingP95 = 0.01;

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.scenario;
}

class FftRendered : public ::testing::TestWithParam<Case> {};

TEST_P(FftRendered, AccuracyWithinIssueBounds) {
  const Case c = GetParam();
  const sim::Scenario s =
      testing::shipped_scenario(std::string(c.scenario) + ".yaml", c.duration_s);
  const testing::RenderedRun run = testing::render_and_run(s);
  const NetPoseAccuracy a = score_net_pose(run.dataset, run.rows, NetPoseSource::kFft);
  const RunSummary& summary = run.summary;

  SCOPED_TRACE(std::string(c.scenario) + ":\n" + describe(a));
  EXPECT_EQ(summary.frames, static_cast<size_t>(s.num_frames()));
  EXPECT_EQ(a.frames, static_cast<size_t>(s.num_frames()));
  // The error figures cover measurable frames with an estimate only; require enough of them.
  ASSERT_GE(a.measurable_estimated, c.min_estimated);
  EXPECT_LE(a.d_net_rel.median, 0.02);
  EXPECT_LE(a.d_net_rel.p95, 0.05);
  EXPECT_LE(a.psi_net_deg.median, 1.0);
  EXPECT_LE(a.psi_net_deg.p95, 3.0);
  EXPECT_LE(static_cast<double>(a.gross_errors), 0.02 * static_cast<double>(a.frames));
}

// The whole sweep: it opens and closes on open water (no net), and runs 0.43-2.6 m with the
// heading swinging +-17 deg. Turbid and low light: their first 3 s. solaqua: a real pen's
// sheared, fouled 27.5 mm mesh at 1280x720, soft, colour and JPEG, its first 1 s (0.53 %
// median over the whole run).
INSTANTIATE_TEST_SUITE_P(Scenarios, FftRendered,
                         ::testing::Values(Case{"sweep", 0, 30}, Case{"turbid", 3, 25},
                                           Case{"lowlight", 3, 25}, Case{"solaqua", 1, 10}),
                         [](const auto& param_info) {
                           return std::string(param_info.param.scenario);
                         });

// A whole shipped scenario of issue 37's clutter, its noise, marine snow and fouling drawn from
// the test's seed, scored against the truth: d_net's median within the issue's 0.5 %, no frame
// more than 20 % off, the rest within `bounds`.
struct ClutterBounds {
  size_t min_estimated;
  double max_p95, max_psi_median_deg;
};

void expect_within(const char* scenario, const ClutterBounds& bounds) {
  sim::Scenario s = testing::shipped_scenario(std::string(scenario) + ".yaml");
  s.seed = testing::fresh_seed();
  const testing::RenderedRun run = testing::render_and_run(s);
  const NetPoseAccuracy a = score_net_pose(run.dataset, run.rows, NetPoseSource::kFft);
  std::printf("%s", describe(a).c_str());
  ASSERT_EQ(a.measurable, static_cast<size_t>(s.num_frames()));
  EXPECT_GE(a.measurable_estimated, bounds.min_estimated);
  EXPECT_LE(a.d_net_rel.median, 0.005);
  EXPECT_LE(a.d_net_rel.p95, bounds.max_p95);
  EXPECT_LE(a.psi_net_deg.median, bounds.max_psi_median_deg);
  EXPECT_EQ(a.gross_errors, 0u);
}

// Issue 37's cluttered wall (scenarios/ropes_seams_fish.yaml, the whole 12 s): ropes along the
// twines, seams and fish in view. Bounds: the issue's for psi's median, d_net's p95 and the
// frames with a pose from the tail.
TEST(FftRendered, RopesSeamsAndFishInView) {
  expect_within("ropes_seams_fish", {kMinRopesEstimated, kMaxRopesP95, 0.5});
}

// Issue 37's fold (scenarios/fold.yaml, the whole 12 s): a ridge and a valley, each panel turned
// 13 deg, whose fold lines cross the view at 1.0-1.6 m. Bounds: the frames with a pose, d_net's
// p95 and psi's median from the tail.
TEST(FftRendered, AFoldInView) {
  expect_within("fold", {kMinFoldEstimated, kMaxFoldP95, kMaxFoldPsiMedian_deg});
}

// Looking along the net 35-51 deg off its normal (scenarios/oblique.yaml, 6 s): a pose on every
// frame, distances within the measured tail. The evaluation's envelope stops at 35 deg, so the
// frames beyond are scored here against the truth row by row.
TEST(FftRendered, ObliqueViewsGiveAPose) {
  sim::Scenario s = testing::shipped_scenario("oblique.yaml");
  s.seed = testing::fresh_seed();
  const testing::RenderedRun run = testing::render_and_run(s);
  const std::vector<GroundTruthRow>& truth = run.dataset.groundtruth0->rows;
  ASSERT_EQ(truth.size(), run.rows.size());
  std::vector<double> errors;
  size_t oblique = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    ASSERT_EQ(truth[i].timestamp_ns, run.rows[i].timestamp_ns);
    if (std::abs(truth[i].psi_net_rad) < deg_to_rad(35.0)) continue;
    ++oblique;
    const double d = run.rows[i].d_net_fft_m;
    if (std::isfinite(d)) errors.push_back(std::abs(d / truth[i].d_net_m - 1));
  }
  ASSERT_GE(oblique, 40u);
  EXPECT_GE(static_cast<double>(errors.size()), 0.9 * static_cast<double>(oblique));
  const ErrorStats e = error_stats(errors);
  std::printf("oblique frames %zu, with a pose %zu, d_net rel. error median %.2f%% max %.2f%%\n",
              oblique, errors.size(), 100 * e.median, 100 * e.max);
  EXPECT_LE(e.median, kMaxObliqueMedian);
  EXPECT_LE(e.max, kMaxObliqueMax);
}

// A net that changes every 0.8 s (scenarios/changing_net.yaml: square 90-108 deg and diamond
// 72-116 deg, thin and thick twines, knots, fouling): the first frame of every new net has a pose
// within the measured tail, and the whole run's error stays that of one net. The carried opening
// angle is a prior: a frame that disagrees with it is solved on its own.
TEST(FftRendered, AChangingNetRecoversOnItsFirstFrame) {
  sim::Scenario s = testing::shipped_scenario("changing_net.yaml");
  s.seed = testing::fresh_seed();
  ASSERT_GE(s.net_changes.size(), 6u);
  const testing::RenderedRun run = testing::render_and_run(s);
  const std::vector<GroundTruthRow>& truth = run.dataset.groundtruth0->rows;
  ASSERT_EQ(truth.size(), run.rows.size());
  std::vector<double> first_frame_errors, errors;
  size_t firsts = 0, net_index = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    ASSERT_EQ(truth[i].timestamp_ns, run.rows[i].timestamp_ns);
    const size_t k = s.net_index_at(sim::frame_state(s, static_cast<int>(i)).t_s);
    const bool first = k != net_index;
    net_index = k;
    const double d = run.rows[i].d_net_fft_m;
    const double error = std::isfinite(d) ? std::abs(d / truth[i].d_net_m - 1) : kNaN;
    if (std::isfinite(error)) errors.push_back(error);
    if (!first) continue;
    ++firsts;
    SCOPED_TRACE("frame " + std::to_string(i) + ", net " + std::to_string(k));
    EXPECT_TRUE(std::isfinite(error));
    if (std::isfinite(error)) first_frame_errors.push_back(error);
  }
  EXPECT_EQ(firsts, s.net_changes.size());
  const ErrorStats first_e = error_stats(first_frame_errors), e = error_stats(errors);
  std::printf(
      "changing net: %zu frames, %zu with a pose, d_net rel. error median %.2f%% p95 "
      "%.2f%% max %.2f%%; changes' first frames %zu of %zu with a pose, max %.2f%%\n",
      truth.size(), errors.size(), 100 * e.median, 100 * e.p95, 100 * e.max,
      first_frame_errors.size(), firsts, 100 * first_e.max);
  EXPECT_GE(errors.size(), kMinChangingEstimated);
  EXPECT_LE(e.median, 0.005);
  EXPECT_LE(e.p95, kMaxChangingP95);
  EXPECT_LE(first_e.max, kMaxChangingP95);
}

// Issue 45's cameras: the sweep's first 4 s (turned away, then the net at 0.5-2.65 m with the
// heading swinging) at the reference field of view on frames from 320x180 to 3840x2160, with the
// ROI side and FFT size planned from the camera (grid_plan.h): a pose on >= 95 % of the
// measurable frames, none on the frames without a net, d_net median <= 0.5 % and psi median <=
// 0.5 deg. Measured (docs/validation-log.md 2026-12-06): 29 of 29 frames on every size and seed,
// d_net medians 0.07-0.30 %, psi medians 0.22-0.33 deg; at 320x180 the far frames' bars are
// 2.3-3 px. Frames above 1920x1080 are rendered at 5 Hz (the same 4 s, half the frames): a 4K
// frame takes ~2.5 s to render on lavapipe, and the view changes little in 0.1 s.
struct CameraSize {
  int width, height;
};

void PrintTo(const CameraSize& c, std::ostream* os) {
  *os << c.width << "x" << c.height;
}

class FftRenderedCamera : public ::testing::TestWithParam<CameraSize> {};

TEST_P(FftRenderedCamera, APoseFromAnyFrameSize) {
  const CameraSize c = GetParam();
  sim::Scenario s = testing::shipped_scenario("sweep.yaml", 4.0);
  s.seed = testing::fresh_seed();
  s.camera.calibration.camera = default_field_of_view(c.width, c.height);
  if (c.width * c.height > 1920 * 1080) s.camera.calibration.rate_hz = 5;
  sim::validate(s);
  const testing::RenderedRun run = testing::render_and_run(s);
  const NetPoseAccuracy a = score_net_pose(run.dataset, run.rows, NetPoseSource::kFft);
  std::printf("%dx%d: %s", c.width, c.height, describe(a).c_str());
  ASSERT_GE(static_cast<double>(a.measurable), 2 * s.camera.calibration.rate_hz);
  EXPECT_GE(static_cast<double>(a.measurable_estimated), 0.95 * static_cast<double>(a.measurable));
  EXPECT_LE(a.d_net_rel.median, 0.005);
  EXPECT_LE(a.psi_net_deg.median, 0.5);
  EXPECT_EQ(a.gross_errors, 0u);
}

// A far net's frames against the truth: a pose on kMinFarShare of them, its d_net within the far
// bounds; `what` names the case in the printed line.
void expect_far_net_read(const testing::RenderedRun& run, const std::string& what) {
  const std::vector<GroundTruthRow>& truth = run.dataset.groundtruth0->rows;
  ASSERT_EQ(truth.size(), run.rows.size());
  std::vector<double> errors;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double d = run.rows[i].d_net_fft_m;
    if (std::isfinite(d)) errors.push_back(std::abs(d / truth[i].d_net_m - 1));
  }
  const ErrorStats e = error_stats(errors);
  std::printf("%s: %zu of %zu frames with a pose, d_net rel. error median %.2f%% max %.2f%%\n",
              what.c_str(), errors.size(), truth.size(), 100 * e.median, 100 * e.max);
  EXPECT_GE(static_cast<double>(errors.size()), kMinFarShare * static_cast<double>(truth.size()));
  EXPECT_LE(e.median, kMaxFarMedian);
  EXPECT_LE(e.max, kMaxFarMax);
}

// A 30 mm net 6.2 m from a 1280x720 camera: 4 px bars, finer than the planned 533 px ROIs at
// FFT 256 hold (4.6 px), which read such a net as one 2-3x nearer. The fine-mesh probe sends the
// frames to native 256 px ROIs, which read the true distance.
TEST(FftRenderedFar, ANetFinerThanThePlannedRoisHoldIsReadOnNativeRois) {
  sim::Scenario s = testing::shipped_scenario("follow.yaml", 1.0);
  s.seed = testing::fresh_seed();
  s.camera.calibration.camera = default_field_of_view(1280, 720);
  s.water.attenuation_per_m = 0.15;
  s.water.backscatter = 0.2;
  s.water.marine_snow = 0;
  s.waypoints = {{.t_s = 0, .net_distance_m = 6.5, .depth_m = 4.0, .heading_rad = 0.15},
                 {.t_s = 1, .along_m = 0.1, .net_distance_m = 6.6, .depth_m = 4.0}};
  sim::validate(s);
  expect_far_net_read(testing::render_and_run(s), "far net");
}

// A fouled 44 mm net 3.1-3.5 m from the reference 720x540 camera: the planned 443 px ROIs would
// hold ~65 periods at FFT 256, and their band's low end the fouling's clean patches ~100 px apart
// (a random training scene read 0.21 m for 3.3 m from them). The probe sends the frames to native
// 256 px ROIs.
TEST(FftRenderedFar, AFouledNetBeyondThePlannedGridsReachIsReadOnNativeRois) {
  std::mt19937_64 rng(testing::fresh_seed());
  sim::Scenario s = testing::shipped_scenario("follow.yaml", 1.0);
  s.seed = rng();
  s.camera.calibration.camera = default_field_of_view(720, 540);
  s.net.bar_length_m = 0.044;
  s.net.twine_width_m = 0.009;
  s.net.fouling = 0.2;
  s.net.fouling_coverage = 0.5;
  s.water.marine_snow = 0;
  const double distance_m = std::uniform_real_distribution<double>(3.1, 3.5)(rng);
  const double heading_rad = std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
  s.waypoints = {
      {.t_s = 0, .net_distance_m = distance_m, .depth_m = 4.0, .heading_rad = heading_rad},
      {.t_s = 1,
       .along_m = 0.1,
       .net_distance_m = distance_m,
       .depth_m = 4.0,
       .heading_rad = heading_rad}};
  sim::validate(s);
  char what[96];
  std::snprintf(what, sizeof what, "fouled net at %.2f m, heading %.2f rad", distance_m,
                heading_rad);
  expect_far_net_read(testing::render_and_run(s), what);
}

INSTANTIATE_TEST_SUITE_P(Sizes, FftRenderedCamera,
                         ::testing::Values(CameraSize{320, 180}, CameraSize{640, 480},
                                           CameraSize{1280, 720}, CameraSize{1920, 1080},
                                           CameraSize{3840, 2160}),
                         [](const auto& param_info) {
                           return std::to_string(param_info.param.width) + "x" +
                                  std::to_string(param_info.param.height);
                         });

}  // namespace
}  // namespace pensight
