// The acceptance of the rendered closed loop on a shipped scenario (issue 14): holding 0.5 m on
// the vehicle's own perception, with each velocity strategy. A full 40 s run per strategy; the
// other scenarios are measured in docs/control.md.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "sim/closed_loop.h"
#include "sim/closed_loop_report.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::sim {
namespace {

TEST(ClosedLoopAccuracy, HoldsHalfAMetreOnRenderedFramesWithEitherStrategy) {
  const char* dir = std::getenv("PENSIGHT_SOURCE_DIR");
  Scenario s = load_scenario(std::filesystem::path(dir ? dir : ".") / "scenarios/hold_0p5.yaml");
  s.duration_s = 25;
  validate(s);
  for (const auto strategy :
       {control::VelocityStrategy::kDvlFeedback, control::VelocityStrategy::kOpenLoop}) {
    SCOPED_TRACE(control::to_string(strategy));
    ClosedLoopOptions options;
    options.strategy = strategy;
    const auto out = std::filesystem::temp_directory_path() / "pensight_closed_loop_accuracy";
    const ClosedLoopSummary summary = run_closed_loop(s, out, options, testing::test_device());
    const ClosedLoopMetrics m = closed_loop_metrics(summary.steps);
    std::printf("%s: distance RMSE %.2f cm, heading RMSE %.2f deg, settled after %.1f s\n",
                control::to_string(strategy), 100 * m.distance_rmse_m, m.heading_rmse_deg,
                m.legs.empty() ? -1.0 : m.legs.front().settle_s);
    EXPECT_GT(m.settled_steps, 100);
    EXPECT_LT(m.distance_rmse_m, strategy == control::VelocityStrategy::kDvlFeedback ? 0.03 : 0.06);
    EXPECT_LT(m.heading_rmse_deg, 2.0);
    ASSERT_EQ(m.legs.size(), 1u);
    EXPECT_LT(m.legs.front().settle_s, 10);
    EXPECT_LT(m.legs.front().overshoot_m, 0.10);
    std::filesystem::remove_all(out);
  }
}

}  // namespace
}  // namespace pensight::sim
