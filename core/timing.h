#pragma once
// Clocks and wall-clock timing for the host side of the pipeline (device times come from
// vk::CommandStream::timings(); per-stage statistics from pipeline/stage_stats.h).
#include <algorithm>
#include <chrono>
#include <cstdint>

namespace pensight {

// The monotonic clock, ns: timeouts, rates, reconnect delays.
inline int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The host's wall clock, ns since the Unix epoch: the time stamps of live sensor samples.
inline int64_t host_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A span in ns as poll()'s timeout in ms: rounded up (a wait never ends early), at most 60 s.
inline int poll_timeout_ms(int64_t ns) {
  return static_cast<int>(std::clamp<int64_t>((ns + 999'999) / 1'000'000, 0, 60'000));
}

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
