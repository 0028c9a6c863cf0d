// validate(NetDetectorConfig) and the detector's parameter rows: a value out of range anywhere in
// the config gives the one message of core/params.h, with the key of the part that holds it.
#include "pipeline/fft/net_detector_params.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "core/params.h"
#include "core/strict_yaml.h"
#include "core/units.h"
#include "tests/support/error_message.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

// The message validate() throws for `c`; empty when it passes.
std::string error_of(const NetDetectorConfig& c) {
  return testing::error_message([&] { validate(c); });
}

TEST(NetDetectorParams, DefaultsAndTheConfigsInUseAreValid) {
  EXPECT_EQ(error_of({}), "");
  // The published method of the ablation (fft_tables.cpp): FFT size 300 on the CPU, rules off.
  NetDetectorConfig published{
      .fft_size = 300, .window = false, .backend = Backend::kCpu, .cpu_threads = 1};
  published.peaks.subharmonic_ratio = 1e9f;
  published.points.min_quality = 0;
  published.pose.inlier_rel = 1e9;
  published.pose.max_curvature_share = 1e9;
  EXPECT_EQ(error_of(published), "");
  // The one-ROI grid of bench/pipeline_bench.cpp, a scene's opening angle, a still filter.
  NetDetectorConfig small{.grid = {.rows = 1, .cols = 1, .roi_size_px = 64}, .fft_size = 32};
  small.mesh_angle_rad = deg_to_rad(30);
  small.mesh_angle_filter.process_sigma_rad = 0;
  EXPECT_EQ(error_of(small), "");
}

TEST(NetDetectorParams, ABadValueInAPartNamesItsPrefixedKey) {
  NetDetectorConfig c;
  c.peaks.min_cycles = -1;
  const std::string e = error_of(c);
  EXPECT_TRUE(
      e.starts_with("net detector config: key 'peaks.min_cycles': -1 is outside > 0 cycles ("))
      << e;
  // The constructor refuses it with the same message, before it plans anything.
  try {
    NetDetector(PinholeCamera{}, c, testing::test_device());
    ADD_FAILURE() << "no error";
  } catch (const Error& constructor) {
    EXPECT_EQ(constructor.what(), e);
  }

  const testing::SpoiltConfig<NetDetectorConfig> bad[] = {
      {"key 'peaks.max_nyquist_share': none is outside (0, 1] (",
       [](NetDetectorConfig& x) { x.peaks.max_nyquist_share = std::nanf(""); }},
      {"key 'points.max_range_m': none is outside > 0 m (",
       [](NetDetectorConfig& x) { x.points.max_range_m = kNaN; }},
      {"key 'grid.rows': 0 is outside >= 1 (", [](NetDetectorConfig& x) { x.grid.rows = 0; }},
      {"key 'pose.min_valid_rois': 2 is outside >= 3 (",
       [](NetDetectorConfig& x) { x.pose.min_valid_rois = 2; }},
      {"key 'priors.spacing_share': 0.7 is outside (0, 0.5] (",
       [](NetDetectorConfig& x) { x.priors.spacing_share = 0.7; }},
      {"key 'texture.min_coherence': 2 is outside 0 to 1 (",
       [](NetDetectorConfig& x) { x.texture.min_coherence = 2; }},
      {"key 'mesh_angle.min_rois': 0 is outside >= 1 (",
       [](NetDetectorConfig& x) { x.mesh_angle.min_rois = 0; }},
      {"key 'mesh_angle_filter.min_sigma_rad': 0 is outside > 0 rad (",
       [](NetDetectorConfig& x) { x.mesh_angle_filter.min_sigma_rad = 0; }},
      {"key 'bar_length_m': 0 is outside > 0 m (",
       [](NetDetectorConfig& x) { x.bar_length_m = 0; }},
      {"key 'mesh_angle_rad': 3.14159 is outside (0, 3.14159) rad (",
       [](NetDetectorConfig& x) { x.mesh_angle_rad = std::numbers::pi; }},
  };
  testing::expect_refused(
      bad, "net detector config: ", [](const NetDetectorConfig& spoilt) { validate(spoilt); });
}

TEST(NetDetectorParams, CrossRulesNameTheKey) {
  NetDetectorConfig larger;
  larger.grid.roi_size_px = 300;
  larger.fft_size = 512;  // above the 300 px ROI
  EXPECT_TRUE(error_of(larger).starts_with("net detector config: key 'fft_size': 512 px is above"))
      << error_of(larger);
  NetDetectorConfig odd{.fft_size = 200};  // kAuto may choose a GPU path
  EXPECT_TRUE(error_of(odd).starts_with("net detector config: key 'fft_size': 200 px is not"))
      << error_of(odd);
  odd.backend = Backend::kCpu;
  EXPECT_EQ(error_of(odd), "");
  NetDetectorConfig no_band;
  no_band.fft_size = 256;
  no_band.peaks.min_cycles = 120;  // the band ends at 0.9 * 128 = 115.2 cycles
  EXPECT_TRUE(error_of(no_band).starts_with(
      "net detector config: key 'peaks.min_cycles': 120 cycles leaves no"))
      << error_of(no_band);
  // 0 plans the side (grid_plan.h); 1-15 are too small.
  NetDetectorConfig tiny;
  tiny.grid.roi_size_px = 8;
  EXPECT_TRUE(error_of(tiny).starts_with(
      "net detector config: key 'grid.roi_size_px': 8 px is below 16; give 16 or more, or 0"))
      << error_of(tiny);
  tiny.grid.roi_size_px = 0;
  tiny.fft_size = 8;
  EXPECT_TRUE(error_of(tiny).starts_with("net detector config: key 'fft_size': 8 px is below 16"))
      << error_of(tiny);
}

TEST(NetDetectorParams, RowsListEveryPartUnderItsPrefix) {
  const std::string table = net_detector_param_rows();
  std::string rows("\n");  // each row then follows a line break
  rows += table;
  for (const char* row : {
           "| `fft_size` | 0 | px | 0 to 1024 |",
           "| `window` | true |  | true, false |",
           "| `mesh_angle_rad` | none | rad | (0, 3.14159) |",
           "| `grid.roi_size_px` | 0 | px | >= 0 |",
           "| `peaks.max_nyquist_share` | 0.9 |  | (0, 1] |",
           "| `points.min_quality` | 0.03 |  | 0 to 1 |",
           "| `pose.min_valid_rois` | 6 |  | >= 3 |",
           "| `priors.per_axis` | 3 |  | >= 1 |",
           "| `texture.window_px` | 256 | px | >= 8 |",
           "| `mesh_angle.max_bar_mismatch` | 0.15 |  | 0 to 1 |",
           "| `mesh_angle_filter.restart_after` | 3 |  | >= 1 |",
       }) {
    EXPECT_NE(rows.find(std::string("\n") + row), std::string::npos) << row << "\n" << rows;
  }
  // A '|' in a help text would split its cell.
  EXPECT_EQ(std::count(table.begin(), table.end(), '|'),
            6 * std::count(table.begin(), table.end(), '\n'))
      << table;
}

// core/params.h's float members (PeakParams): read, range-checked and shown as written.
TEST(NetDetectorParams, FloatMembersReadAsWritten) {
  const Param<kernels::PeakParams> table[] = {{"max_nyquist_share",
                                               &kernels::PeakParams::max_nyquist_share,
                                               "",
                                               {0, 1, true, false},
                                               "share"}};
  kernels::PeakParams peaks;
  read_params<kernels::PeakParams>(YamlMap::parse("max_nyquist_share: 0.8\n", "peaks.yaml"), table,
                                   peaks);
  EXPECT_EQ(peaks.max_nyquist_share, 0.8f);
  EXPECT_EQ(param_value(peaks, table[0]), static_cast<double>(0.8f));
  EXPECT_EQ(param_table_rows<kernels::PeakParams>(table, peaks),
            "| `max_nyquist_share` | 0.8 |  | (0, 1] | share |\n");
  EXPECT_THROW(read_params<kernels::PeakParams>(
                   YamlMap::parse("max_nyquist_share: 1.5\n", "peaks.yaml"), table, peaks),
               Error);
}

}  // namespace
}  // namespace pensight
