// The shipped depth network on held-out renders of shipped scenarios (never in its training
// draw), through the depth stage: within bounds set from what docs/dense_depth.md measured on
// their first 40 frames (the renders are deterministic per scenario, so there is no seed tail),
// and no worse than 3x S1 alone on the same pixels. Full table: pensight depth-eval.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/csv.h"
#include "core/median.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/depth/depth_accuracy.h"
#include "tests/support/rendered_run.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {

struct Case {
  const char* scenario;
  double abs_rel, d_net_rel, psi_rad;  // bounds
};

// The shipped model's accuracy on every 2nd frame of `d` (the FFT stage on the CPU for priors).
DepthAccuracy shipped_model_accuracy(const Dataset& d) {
  NetDetector detector(d.cam0.camera, detector_config(d.scene, {.backend = Backend::kCpu}),
                       testing::test_device());
  const std::filesystem::path model =
      std::filesystem::path(std::getenv("PENSIGHT_SOURCE_DIR")) / "models/compact_depth.onnx";
  DepthEstimator estimator(d.cam0.camera,
                           {.model = model, .net_curvature_per_m = net_curvature_per_m(d.scene)},
                           testing::test_device());
  return depth_accuracy(d, detector, estimator, 2);
}

class DenseDepthRendered : public ::testing::TestWithParam<Case> {};

TEST_P(DenseDepthRendered, ShippedModelWithinBounds) {
  const Case c = GetParam();
  const testing::RenderedDataset rendered(
      testing::shipped_scenario(std::string(c.scenario) + ".yaml", 1.0));
  const DepthAccuracy a = shipped_model_accuracy(rendered.dataset());
  SCOPED_TRACE(::testing::Message()
               << c.scenario << ": AbsRel " << a.network.abs_rel << " (S1 " << a.s1.abs_rel
               << ", plane " << a.fft_plane.abs_rel << "), delta1 " << a.network.delta1
               << ", d_net " << a.d_net_median_rel << ", psi " << a.psi_median_rad);
  ASSERT_GE(a.frames, 5u);
  EXPECT_LE(a.network.abs_rel, c.abs_rel);
  EXPECT_LE(a.network.abs_rel, 3 * a.s1.abs_rel);
  EXPECT_GE(a.network.delta1, 0.99);
  EXPECT_LE(a.d_net_median_rel, c.d_net_rel);
  EXPECT_LE(a.psi_median_rad, c.psi_rad);
}

// Measured (40 frames, 2026-12-04 model): follow AbsRel 0.32 %, d_net 0.17 %, psi 0.05 deg;
// lowlight 0.22 %, 0.06 %, 0.09 deg; along_12m 0.25 %, 0.19 %, 0.11 deg. The bounds are 3x the
// 2026-12-02 model's AbsRel (0.49 / 0.84 / 0.35 %) and d_net (0.21 %); the present model is
// within all of them.
INSTANTIATE_TEST_SUITE_P(Shipped, DenseDepthRendered,
                         ::testing::Values(Case{"follow", 0.015, 0.0065, 0.0042},
                                           Case{"lowlight", 0.025, 0.005, 0.0037},
                                           Case{"along_12m", 0.011, 0.0065, 0.0063}),
                         [](const auto& p) { return std::string(p.param.scenario); });

// The frames of a `pensight run` whose depth_scale (diagnostics.csv) is not 1, with the scale,
// and every frame's d_net errors against the truth (FFT, dense depth).
struct ScaledRun {
  std::vector<double> scales, fft_errors, depth_errors;
  std::vector<bool> scaled;
};

ScaledRun run_with_scale(const Dataset& d, bool dvl_depth_scale) {
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  options.depth =
      DepthEstimatorConfig{.model = std::filesystem::path(std::getenv("PENSIGHT_SOURCE_DIR")) /
                                    "models/compact_depth.onnx",
                           .net_curvature_per_m = net_curvature_per_m(d.scene)};
  options.dvl_depth_scale = dvl_depth_scale;
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("pensight-dvl-scale-" + std::to_string(::getpid()));
  run_dataset(d, out, options, testing::test_device());
  const std::vector<EstimateRow> rows = read_estimates_csv(out / "estimates.csv");
  const CsvTable diag(out / kDiagnosticsFile, 1, 100);
  std::filesystem::remove_all(out);
  const auto& header = diag.header();
  const size_t scale_column =
      std::find(header.begin(), header.end(), "depth_scale") - header.begin();
  EXPECT_LT(scale_column, header.size());
  EXPECT_EQ(diag.rows(), rows.size());
  ScaledRun r;
  for (size_t i = 0; i < rows.size() && scale_column < header.size(); ++i) {
    const GroundTruthRow* truth = d.truth_for_frame(i);
    if (!truth || !std::isfinite(rows[i].d_net_depth_m)) continue;
    r.scales.push_back(diag.number(i, scale_column));
    r.scaled.push_back(r.scales.back() != 1);
    r.fft_errors.push_back(std::abs(rows[i].d_net_fft_m / truth->d_net_m - 1));
    r.depth_errors.push_back(std::abs(rows[i].d_net_depth_m / truth->d_net_m - 1));
  }
  return r;
}

// `pensight run` on a net whose bars are 4 % longer than scene.yaml says (a stretched net, or a
// nominal mesh size off): the FFT's d_net and the camera's dense depth are 4 % too near, the
// DVL's beam ranges are not. Once the DVL's scale engages (2 s in) the dense depth's d_net follows
// the truth (measured 0.47 % median, scale 1.046-1.047); with --no-dvl-scale it stays 4 % off.
TEST(DenseDepthRenderedDvl, TheDvlScalesANetLongerThanSceneYamlSays) {
  const testing::RenderedDataset rendered(testing::shipped_scenario("follow.yaml", 3.5));
  Dataset d = rendered.dataset();
  d.scene.bar_length_m /= 1.04;
  const ScaledRun with = run_with_scale(d, true);
  std::vector<double> fft, depth;
  for (size_t i = 0; i < with.scales.size(); ++i) {
    if (!with.scaled[i]) continue;
    EXPECT_NEAR(with.scales[i], 1.04, 0.015) << "frame " << i;
    fft.push_back(with.fft_errors[i]);
    depth.push_back(with.depth_errors[i]);
  }
  ASSERT_GE(depth.size(), 10u);
  EXPECT_GT(median(fft), 0.03);
  EXPECT_LT(median(depth), 0.01);

  const ScaledRun without = run_with_scale(d, false);
  ASSERT_EQ(without.scales.size(), with.scales.size());
  for (double s : without.scales) EXPECT_EQ(s, 1.0);
  EXPECT_GT(median(without.depth_errors), 0.03);
}

// Issue 45: a camera of another aspect. follow.yaml through a 720x576 camera of the same lens:
// the 4:3 model runs on its centred 720x540 crop (depth_input.h), which is the 720x540 camera's
// whole view, so the follow case's bounds above hold on the pixels it covers.
TEST(DenseDepthRenderedAspect, A720x576CameraGetsDepthOnItsCentredCrop) {
  sim::Scenario s = testing::shipped_scenario("follow.yaml", 1.0);
  PinholeCamera& k = s.camera.calibration.camera;
  k.height_px = 576;
  k.cy_px = 287.5;
  sim::validate(s);
  const testing::RenderedDataset rendered(s);
  const DepthAccuracy a = shipped_model_accuracy(rendered.dataset());
  SCOPED_TRACE(::testing::Message() << "AbsRel " << a.network.abs_rel << " (S1 " << a.s1.abs_rel
                                    << "), delta1 " << a.network.delta1 << ", d_net "
                                    << a.d_net_median_rel << ", psi " << a.psi_median_rad);
  ASSERT_GE(a.frames, 5u);
  EXPECT_LE(a.network.abs_rel, 0.015);
  EXPECT_GE(a.network.delta1, 0.99);
  EXPECT_LE(a.d_net_median_rel, 0.0065);
  EXPECT_LE(a.psi_median_rad, 0.0042);
}

}  // namespace
}  // namespace pensight
