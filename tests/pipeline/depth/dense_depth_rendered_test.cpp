// The shipped depth network on held-out renders of shipped scenarios (never in its training
// draw), through the depth stage: within bounds set from what docs/dense_depth.md measured on
// their first 40 frames (the renders are deterministic per scenario, so there is no seed tail),
// and no worse than 3x S1 alone on the same pixels. Full table: pensight depth-eval.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "pipeline/depth/depth_accuracy.h"
#include "pipeline/runner.h"
#include "tests/support/rendered_run.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

struct Case {
  const char* scenario;
  double abs_rel, d_net_rel, psi_rad;  // bounds
};

class DenseDepthRendered : public ::testing::TestWithParam<Case> {};

TEST_P(DenseDepthRendered, ShippedModelWithinBounds) {
  const Case c = GetParam();
  const testing::RenderedDataset rendered(
      testing::shipped_scenario(std::string(c.scenario) + ".yaml", 1.0));
  const Dataset& d = rendered.dataset();
  NetDetector detector(d.cam0.camera, detector_config(d.scene, {.backend = Backend::kCpu}),
                       testing::test_device());
  const std::filesystem::path model =
      std::filesystem::path(std::getenv("PENSIGHT_SOURCE_DIR")) / "models/compact_depth.onnx";
  DepthEstimator estimator(d.cam0.camera,
                           {.model = model, .net_curvature_per_m = net_curvature_per_m(d.scene)},
                           testing::test_device());
  const DepthAccuracy a = depth_accuracy(d, detector, estimator, 2);
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

}  // namespace
}  // namespace pensight
