#include "pipeline/evaluation/evaluation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "runtime/error.h"

namespace pensight {
namespace {

GroundTruthRow truth(int64_t t, double d, double psi_rad, double fraction = 1.0) {
  GroundTruthRow r;
  r.timestamp_ns = t;
  r.d_net_m = d;
  r.psi_net_rad = psi_rad;
  r.pitch_net_rad = 0;
  r.net_fraction = fraction;
  return r;
}

EstimateRow estimate(int64_t t, double d, double psi_rad) {
  EstimateRow r;
  r.timestamp_ns = t;
  r.d_net_fft_m = d;
  r.psi_net_fft_rad = psi_rad;
  r.pitch_net_fft_rad = 0;
  return r;
}

TEST(ErrorStats, NearestRankPercentiles) {
  std::vector<double> e;
  for (int i = 1; i <= 100; ++i) e.push_back(i % 2 ? i : -i);
  const ErrorStats s = error_stats(e);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.median, 50);
  EXPECT_DOUBLE_EQ(s.p95, 95);
  EXPECT_DOUBLE_EQ(s.max, 100);
  EXPECT_EQ(error_stats({}).count, 0u);
}

TEST(ScoreNetPose, EnvelopeAndGrossErrors) {
  Dataset ds;
  ds.groundtruth0.emplace();
  auto& t = ds.groundtruth0->rows;
  t = {truth(1, 1.0, 0.0),      truth(2, 1.0, 0.1), truth(3, 3.0, 0.0),  // 3: beyond 2.5 m
       truth(4, 1.0, 0.0, 0.2),                                          // 4: net fills 20%
       truth(5, NAN, NAN, 0.0), truth(6, 1.0, 0.0)};                     // 5: axis misses the net
  const std::vector<EstimateRow> rows = {
      estimate(1, 1.01, 0.0), estimate(2, 0.98, 0.1 + 0.01745329),
      estimate(3, 2.0, 0.0),  estimate(4, 1.0, 0.0),
      estimate(5, 0.7, 0.0),  estimate(6, NAN, NAN),
      estimate(99, 1.0, 0.0)};  // no truth row: not scored
  const NetPoseAccuracy a = score_net_pose(ds, rows, NetPoseSource::kFft);
  EXPECT_EQ(a.frames, 6u);
  EXPECT_EQ(a.measurable, 3u);  // 1, 2, 6
  EXPECT_EQ(a.measurable_estimated, 2u);
  EXPECT_NEAR(a.d_net_rel.max, 0.02, 1e-12);
  EXPECT_NEAR(a.psi_net_deg.max, 1.0, 1e-6);
  EXPECT_EQ(a.gross_errors, 2u);  // 3 (33% off) and 5 (distance where there is no net)
  EXPECT_EQ(score_net_pose(ds, rows, NetPoseSource::kDepth).measurable_estimated, 0u);
  EXPECT_NE(describe(a).find("d_net"), std::string::npos);
}

TEST(ScoreNetPose, NeedsGroundTruth) {
  const Dataset ds;
  EXPECT_THROW(score_net_pose(ds, {}, NetPoseSource::kFft), Error);
}

}  // namespace
}  // namespace pensight
