#include "pipeline/stage_stats.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pensight {
namespace {

TEST(RunningStats, MeanMaxAndNearestRankP95) {
  RunningStats s;
  EXPECT_TRUE(std::isnan(s.mean()) && std::isnan(s.p95()) && std::isnan(s.max()));
  for (int i = 100; i >= 1; --i) s.add(i);
  EXPECT_EQ(s.count(), 100u);
  EXPECT_DOUBLE_EQ(s.mean(), 50.5);
  EXPECT_DOUBLE_EQ(s.p95(), 95);
  EXPECT_DOUBLE_EQ(s.max(), 100);
}

// Memory stays bounded: the percentile covers the last kWindow values, mean and max all of them.
TEST(RunningStats, PercentileOverTheRecentWindow) {
  RunningStats s;
  for (size_t i = 0; i < RunningStats::kWindow; ++i) s.add(1000);
  for (size_t i = 0; i < RunningStats::kWindow; ++i) s.add(1);
  EXPECT_DOUBLE_EQ(s.p95(), 1);
  EXPECT_DOUBLE_EQ(s.max(), 1000);
  EXPECT_DOUBLE_EQ(s.mean(), 500.5);
}

TEST(StageMeter, CountsRateAndLatency) {
  StageMeter m("stage");
  const auto pushed = StageMeter::Clock::now() - std::chrono::milliseconds(20);
  m.add(2.0, pushed);
  const StageStats one = m.stats(3);
  EXPECT_EQ(one.name, "stage");
  EXPECT_EQ(one.processed, 1u);
  EXPECT_EQ(one.dropped, 3u);
  EXPECT_TRUE(std::isnan(one.rate_hz));  // one output has no rate
  EXPECT_GE(one.latency_mean_ms, 20);
  m.add(4.0, pushed);
  EXPECT_DOUBLE_EQ(m.stats().mean_ms, 3.0);
}

}  // namespace
}  // namespace pensight
