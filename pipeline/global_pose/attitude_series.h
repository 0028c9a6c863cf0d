#pragma once
// Attitude samples kept in time order for interpolation at other sensors' timestamps.
#include <cstdint>
#include <deque>
#include <optional>

#include "pipeline/global_pose/measurements.h"

namespace pensight::global_pose {

class AttitudeSeries {
 public:
  // Inserts in timestamp order; false (and nothing stored) for a duplicate timestamp or a
  // non-finite roll or pitch.
  bool insert(const AttitudeSample& s);
  // Roll, pitch and yaw at t: linear between the neighbours (yaw across the wrap), the nearest
  // sample within max_gap_s outside them; nullopt when no sample is that close.
  std::optional<AttitudeSample> at(int64_t t_ns, double max_gap_s) const;
  // The yaw rate [rad/s] at t: the least-squares slope of the yaw (unwrapped) of the samples
  // within [t - window_s, t]; nullopt with fewer than 3 samples or their yaw not finite.
  std::optional<double> yaw_rate(int64_t t_ns, double window_s) const;
  // Drops samples older than t_ns, keeping one before it for interpolation.
  void trim_before(int64_t t_ns);
  bool empty() const { return samples_.empty(); }

 private:
  std::deque<AttitudeSample> samples_;
};

}  // namespace pensight::global_pose
