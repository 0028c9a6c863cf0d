#pragma once
// Per-node timing of a run beside the published Orin pipeline's (its Tab. 3: FFT 47.8 ms,
// TRUDepth 66.8 ms, relative pose 13.2 ms (FFT) / 44.6 ms (TRUDepth), global pose 8.7 ms at 4 Hz,
// wavemap at 0.5 Hz): printed after `pensight run` and written to OUT/timing.csv,
//   #node,count,mean_ms,p95_ms,max_ms,rate_hz,latency_mean_ms,latency_p95_ms,published_mean_ms,
//   published_rate_hz
// one row per node, `nan` where a figure does not exist. Nodes pensight does not run yet keep
// their published row with count 0.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/units.h"
#include "pipeline/stage_stats.h"

namespace pensight {

inline constexpr const char* kTimingFile = "timing.csv";

struct TimingRow {
  StageStats ours;             // count 0: not run
  double published_ms = kNaN;  // NaN: not published
  double published_rate_hz = kNaN;
};

// The published nodes with the stage of the same name (count 0 where none), then the stages
// without a published counterpart (e.g. "load image"), then the end-to-end latency from the
// camera frame's push() to its global pose.
std::vector<TimingRow> timing_table(std::span<const StageStats> stages);

// Fixed-width text table for the terminal.
std::string format_timing_table(std::span<const TimingRow> rows);

// Written whole (temporary name, then rename).
void write_timing_csv(const std::filesystem::path& file, std::span<const TimingRow> rows);

}  // namespace pensight
