#pragma once
// Wall-clock timing for the host side of the pipeline (device times come from
// vk::CommandStream::timings(); per-stage statistics from pipeline/stage_stats.h).
#include <chrono>

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

}  // namespace pensight
