// Issue 45's mesh scales: on every frame size, nets whose cells span from 3 px (a fine mesh far
// away) to 80 px (a coarse one close up), square and diamond, each a short still view of a pen
// wall through `pensight run`'s pipeline with the planned grid, scored row by row against the
// truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/units.h"
#include "sim/scenario.h"
#include "tests/support/rendered_run.h"
#include "tests/support/test_seed.h"
#include "tools/evaluation/evaluation.h"

namespace pensight {
namespace {

struct MeshCase {
  int width, height;
  double bar_m;
  double distance_m;  // camera to net
  MeshType type;
  // The cell's image side, fx bar / distance, for the test's name and the bounds.
  double period_px() const {
    return default_field_of_view(width, height).fx_px * bar_m / distance_m;
  }
};

void PrintTo(const MeshCase& c, std::ostream* os) {
  *os << c.width << "x" << c.height << " " << to_string(c.type) << " " << c.bar_m * 1000
      << " mm at " << c.distance_m << " m";
}

// Issue 45's bounds: a pose on >= 95 % of the frames (4 of 5 here), d_net median <= 1 %,
// <= 0.5 % from 6 px, psi median <= 0.5 deg. Measured over seeds 1-8 (docs/validation-log.md
// 2026-12-07): 5 of 5 frames on every case and seed, d_net medians 0.00-0.26 %, no frame more
// than 0.37 % off, psi medians at most 0.20 deg; the largest error bound is about 3x that. The
// 1280x720 diamond over seeds 1-150 (2026-12-08): medians at most 0.23 %, no frame beyond 0.30 %.
constexpr double kMinShare = 0.8, kMaxMedian = 0.005, kMaxFineMedian = 0.01, kMaxError = 0.01,
                 kMaxPsiMedian_deg = 0.5;

class FftRenderedMesh : public ::testing::TestWithParam<MeshCase> {};

TEST_P(FftRenderedMesh, APoseAtEveryCellSize) {
  const MeshCase c = GetParam();
  sim::Scenario s = testing::shipped_scenario("follow.yaml", 0.4);
  s.seed = testing::fresh_seed();
  s.fish.clear();
  s.camera.calibration.camera = default_field_of_view(c.width, c.height);
  s.net.bar_length_m = c.bar_m;
  s.net.twine_width_m = 0.12 * c.bar_m;
  s.net.knot_size_m = 0.2 * c.bar_m;
  s.net.mesh_type = c.type;
  s.net.opening_angle_deg = c.type == MeshType::kDiamond ? 100 : 90;
  // Clear water far away, as a person would see a net 5-6 m off at all.
  if (c.distance_m > 2.5) {
    s.water.attenuation_per_m = 0.15;
    s.water.backscatter = 0.2;
    s.water.marine_snow = 0;
  }
  // The camera sits 0.3 m ahead of the body origin.
  s.waypoints = {
      {.t_s = 0, .net_distance_m = c.distance_m + 0.3, .depth_m = 4.0, .heading_rad = 0.1},
      {.t_s = 0.4,
       .along_m = 0.05,
       .net_distance_m = c.distance_m + 0.3,
       .depth_m = 4.0,
       .heading_rad = -0.05}};
  sim::validate(s);
  const testing::RenderedRun run = testing::render_and_run(s);
  const std::vector<GroundTruthRow>& truth = run.dataset.groundtruth0->rows;
  ASSERT_EQ(truth.size(), run.rows.size());
  std::vector<double> d_errors, psi_errors_deg;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double d = run.rows[i].d_net_fft_m;
    if (!std::isfinite(d)) continue;
    d_errors.push_back(std::abs(d / truth[i].d_net_m - 1));
    psi_errors_deg.push_back(
        rad_to_deg(std::abs(run.rows[i].psi_net_fft_rad - truth[i].psi_net_rad)));
  }
  const ErrorStats e = error_stats(d_errors), psi = error_stats(psi_errors_deg);
  std::printf(
      "%dx%d %s %.0f mm at %.2f m (%.1f px): %zu of %zu frames with a pose, d_net median "
      "%.2f%% max %.2f%%, psi median %.2f deg\n",
      c.width, c.height, to_string(c.type), c.bar_m * 1000, c.distance_m, c.period_px(),
      d_errors.size(), truth.size(), 100 * e.median, 100 * e.max, psi.median);
  EXPECT_GE(static_cast<double>(d_errors.size()), kMinShare * static_cast<double>(truth.size()));
  EXPECT_LE(e.median, c.period_px() >= 6 ? kMaxMedian : kMaxFineMedian);
  EXPECT_LE(e.max, kMaxError);
  EXPECT_LE(psi.median, kMaxPsiMedian_deg);
}

INSTANTIATE_TEST_SUITE_P(Periods, FftRenderedMesh,
                         ::testing::Values(MeshCase{320, 180, 0.030, 1.54, MeshType::kSquare},
                                           MeshCase{320, 180, 0.030, 0.60, MeshType::kDiamond},
                                           MeshCase{320, 180, 0.050, 0.51, MeshType::kDiamond},
                                           MeshCase{320, 180, 0.050, 0.51, MeshType::kSquare},
                                           MeshCase{640, 480, 0.025, 3.4, MeshType::kSquare},
                                           MeshCase{640, 480, 0.030, 1.2, MeshType::kDiamond},
                                           MeshCase{640, 480, 0.040, 0.41, MeshType::kDiamond},
                                           MeshCase{640, 480, 0.045, 0.31, MeshType::kSquare},
                                           MeshCase{640, 480, 0.060, 0.31, MeshType::kSquare},
                                           MeshCase{640, 480, 0.060, 0.31, MeshType::kDiamond},
                                           MeshCase{1280, 720, 0.030, 2.46, MeshType::kDiamond},
                                           MeshCase{1280, 720, 0.040, 0.41, MeshType::kSquare},
                                           MeshCase{1920, 1080, 0.030, 5.6, MeshType::kSquare},
                                           MeshCase{1920, 1080, 0.040, 0.62, MeshType::kDiamond},
                                           MeshCase{3840, 2160, 0.030, 0.92, MeshType::kSquare}),
                         [](const auto& param_info) {
                           const MeshCase& c = param_info.param;
                           return std::to_string(c.width) + "x" + std::to_string(c.height) + "_" +
                                  to_string(c.type) + "_" +
                                  std::to_string(std::lround(c.period_px())) + "px";
                         });

}  // namespace
}  // namespace pensight
