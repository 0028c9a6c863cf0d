#include "pipeline/stage_stats.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"

namespace pensight {

void RunningStats::add(double value) {
  if (window_.size() < kWindow) {
    window_.push_back(value);
  } else {
    window_[next_] = value;
  }
  next_ = (next_ + 1) % kWindow;
  max_ = count_ == 0 ? value : std::max(max_, value);
  sum_ += value;
  ++count_;
}

double RunningStats::mean() const {
  return count_ ? sum_ / static_cast<double>(count_) : kNaN;
}

double RunningStats::p95() const {
  if (window_.empty()) return kNaN;
  std::vector<double> v = window_;
  const auto rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(rank), v.end());
  return v[rank];
}

double RunningStats::max() const {
  return count_ ? max_ : kNaN;
}

void StageMeter::add(double processing_ms, Clock::time_point pushed) {
  const Clock::time_point now = Clock::now();
  if (processing_.count() == 0) first_ = now;
  last_ = now;
  processing_.add(processing_ms);
  latency_.add(std::chrono::duration<double, std::milli>(now - pushed).count());
}

StageStats StageMeter::stats(size_t dropped) const {
  StageStats s;
  s.name = name_;
  s.processed = processing_.count();
  s.dropped = dropped;
  s.mean_ms = processing_.mean();
  s.p95_ms = processing_.p95();
  s.max_ms = processing_.max();
  const double span_s = std::chrono::duration<double>(last_ - first_).count();
  s.rate_hz = s.processed > 1 && span_s > 0 ? static_cast<double>(s.processed - 1) / span_s : kNaN;
  s.latency_mean_ms = latency_.mean();
  s.latency_p95_ms = latency_.p95();
  return s;
}

}  // namespace pensight
