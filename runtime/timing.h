#pragma once
// Wall-clock stage timing for the host side of the pipeline (device times come from
// vk::CommandStream::timings()).
#include <chrono>
#include <string>
#include <vector>

namespace pensight {

class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

// Accumulates time per named stage in first-seen order, for the end-of-run summary.
class StageTimes {
 public:
  struct Stage {
    std::string name;
    double total_ms = 0;
    long count = 0;
  };

  void add(const std::string& name, double ms);
  const std::vector<Stage>& stages() const { return stages_; }
  // One line per stage: name, calls, mean and total milliseconds.
  std::string summary() const;

 private:
  std::vector<Stage> stages_;
};

}  // namespace pensight
