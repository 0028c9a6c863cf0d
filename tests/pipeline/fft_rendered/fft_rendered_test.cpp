// Issue 4's accuracy acceptance on the synthetic world's own renders: short sequences of the
// shipped scenarios (1 sample per pixel, CPU renderer), through `pensight run`'s pipeline on the
// CPU backend, scored by `pensight evaluate`'s code. Full-length numbers: docs/fft_detection.md.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "tests/support/rendered_run.h"
#include "tools/evaluation/evaluation.h"

namespace pensight {
namespace {

struct Case {
  const char* scenario;
  double duration_s;     // 0: the whole scenario
  size_t min_estimated;  // measurable frames with an estimate: no pass on a handful
};

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

}  // namespace
}  // namespace pensight
