#include "tools/evaluation/evaluation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/units.h"

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
      estimate(1, 1.01, 0.0), estimate(2, 0.98, 0.1 + deg_to_rad(1)),
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
  EXPECT_THROW(score_global_pose(ds, {}), Error);
}

GroundTruthRow pose_truth(int64_t t, double r, double rho_rad, double z, double yaw_rad) {
  GroundTruthRow g;
  g.timestamp_ns = t;
  g.p_pen_body_m = {r * std::cos(rho_rad), r * std::sin(rho_rad), z};
  g.yaw_rad = yaw_rad;
  return g;
}

EstimateRow pose_estimate(int64_t t, double r, double rho_rad, double z, double psi_rad) {
  EstimateRow e;
  e.timestamp_ns = t;
  e.r_g_m = r;
  e.rho_g_rad = rho_rad;
  e.z_g_m = z;
  e.psi_g_rad = psi_rad;
  return e;
}

TEST(ScoreGlobalPose, ErrorsAndChangesFromTheFirstFrameWithRhoAndPsi) {
  Dataset ds;
  ds.groundtruth0.emplace();
  // The truth's azimuth and yaw sit near +-pi so that the changes cross the wrap; the estimate's
  // rho origin (0 at its first frame) differs from the truth's, which must not matter.
  const double rho0 = deg_to_rad(179), yaw0 = -deg_to_rad(179.5);
  ds.groundtruth0->rows = {
      pose_truth(1, 11.2, rho0, 3.0, yaw0),  // no rho/psi estimate: not the reference
      pose_truth(2, 11.2, rho0, 3.0, yaw0),
      pose_truth(3, 11.2, rho0 + deg_to_rad(2), 3.1, yaw0 - deg_to_rad(1)),
      pose_truth(4, 11.2, rho0 + deg_to_rad(4), 3.2, yaw0 - deg_to_rad(2)),
      pose_truth(5, 11.2, rho0 + deg_to_rad(6), 3.3, yaw0)};
  const std::vector<EstimateRow> rows = {
      pose_estimate(1, 11.21, NAN, 3.0, NAN),
      pose_estimate(2, 11.18, 0.0, 3.01, 0.5),                            // reference
      pose_estimate(3, 11.2, deg_to_rad(2), 3.1, 0.5 - deg_to_rad(1.5)),  // psi 0.5 deg off
      pose_estimate(4, NAN, deg_to_rad(4.2), NAN, 0.5 - deg_to_rad(2)),   // rho 0.2 deg off
      pose_estimate(5, 11.3, NAN, 3.3, NAN),
      pose_estimate(9, 11.2, 0.0, 3.0, 0.0)};  // no truth row: not scored
  const GlobalPoseAccuracy a = score_global_pose(ds, rows);
  EXPECT_EQ(a.frames, 5u);
  EXPECT_EQ(a.with_r_g, 4u);
  EXPECT_EQ(a.with_z_g, 4u);
  EXPECT_EQ(a.with_rho_psi, 3u);
  EXPECT_EQ(a.reference_timestamp_ns, 2);
  EXPECT_NEAR(a.r_g_m.max, 0.1, 1e-9);      // frame 5
  EXPECT_NEAR(a.r_g_m.median, 0.01, 1e-9);  // errors 0.01, 0.02, 0, 0.1: nearest rank
  EXPECT_NEAR(a.z_g_m.max, 0.01, 1e-9);
  EXPECT_NEAR(a.rho_change_deg.max, 0.2, 1e-9);
  EXPECT_NEAR(a.psi_change_deg.max, 0.5, 1e-9);
  EXPECT_NEAR(a.psi_change_deg.median, 0.0, 1e-9);
  EXPECT_NE(describe(a).find("psi_g"), std::string::npos);
  // Path from the reference frame: three 2 deg chords at r = 11.2 m; arc errors 0, 0 and
  // 0.2 deg x 11.2 m, all within the last 5 s.
  const double chord = 2 * 11.2 * std::sin(deg_to_rad(1));
  EXPECT_NEAR(a.path_m, 3 * chord, 1e-9);
  EXPECT_NEAR(a.rho_drift_per_m, (deg_to_rad(0.2) * 11.2 / 3) / (3 * chord), 1e-9);
  EXPECT_NE(describe(a).find("rho_g drift"), std::string::npos);
}

// |mean arc error over the last window_s| / path; NaN without frames or path.
TEST(RhoDriftPerMetre, LastWindowOverPath) {
  const std::vector<double> t = {0, 2, 4, 6, 8, 10};
  const std::vector<double> arc = {5, 5, 5, -1, -2, -3};  // only t >= 5 counts
  EXPECT_NEAR(rho_drift_per_m(t, arc, 4.0), 2.0 / 4.0, 1e-12);
  EXPECT_NEAR(rho_drift_per_m(t, arc, 4.0, 20.0), 1.5 / 4.0, 1e-12);
  EXPECT_TRUE(std::isnan(rho_drift_per_m({}, {}, 4.0)));
  EXPECT_TRUE(std::isnan(rho_drift_per_m(t, arc, 0.0)));
}

TEST(ScoreGlobalPose, NoEstimates) {
  Dataset ds;
  ds.groundtruth0.emplace();
  ds.groundtruth0->rows = {pose_truth(1, 12, 0, 3, 0), pose_truth(2, 12, 0, 3, 0)};
  const std::vector<EstimateRow> rows = {pose_estimate(1, NAN, NAN, NAN, NAN),
                                         pose_estimate(2, NAN, NAN, NAN, NAN)};
  const GlobalPoseAccuracy a = score_global_pose(ds, rows);
  EXPECT_EQ(a.frames, 2u);
  EXPECT_EQ(a.with_r_g + a.with_z_g + a.with_rho_psi, 0u);
  EXPECT_EQ(a.reference_timestamp_ns, -1);
  EXPECT_EQ(a.r_g_m.count, 0u);
}

}  // namespace
}  // namespace pensight
