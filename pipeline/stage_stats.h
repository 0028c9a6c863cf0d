#pragma once
// Per-stage timing of the running pipeline: processing time per item and latency from the push()
// of the camera frame to the stage's output, with the output rate. Memory is bounded: mean and
// max cover every item, the 95th percentile the last kWindow items.
#include <array>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace pensight {

// Mean, 95th percentile (nearest rank over the recent window) and max of one quantity.
class RunningStats {
 public:
  static constexpr size_t kWindow = 4096;
  void add(double value);
  size_t count() const { return count_; }
  double mean() const;  // NaN without values
  double p95() const;
  double max() const;

 private:
  std::vector<double> window_;  // ring buffer of the last kWindow values
  size_t next_ = 0;
  size_t count_ = 0;
  double sum_ = 0;
  double max_ = 0;
};

struct StageStats {
  std::string name;  // e.g. "fft net detection"
  size_t processed = 0;
  size_t dropped = 0;  // items a drop-oldest queue discarded before this stage
  double mean_ms = 0;  // processing time per item (NaN when none)
  double p95_ms = 0;
  double max_ms = 0;
  double rate_hz = 0;          // outputs per second of wall time between the first and last output
  double latency_mean_ms = 0;  // push() of the camera frame -> this stage's output
  double latency_p95_ms = 0;
};

// Accumulates one stage's StageStats.
class StageMeter {
 public:
  using Clock = std::chrono::steady_clock;
  explicit StageMeter(std::string name) : name_(std::move(name)) {}
  // One item done: its processing time and when its camera frame was pushed.
  void add(double processing_ms, Clock::time_point pushed);
  StageStats stats(size_t dropped = 0) const;

 private:
  std::string name_;
  RunningStats processing_, latency_;
  Clock::time_point first_, last_;
};

}  // namespace pensight
