#include "pipeline/global_pose/dvl_spike_test.h"

#include <algorithm>
#include <cmath>

namespace pensight::global_pose {

double DvlSpikeTest::difference_noise_mps(const DvlSpikeTestOptions& o) {
  // The difference of two samples has sqrt(2) x one sample's noise per axis, sqrt(3) axes.
  return o.noise_sigmas * o.noise_mps * std::sqrt(6.0);
}

bool DvlSpikeTest::within_bound(int64_t t_ns, const Eigen::Vector3d& v_pen) const {
  const double dt_s = std::abs(seconds_between(reference_ns_, t_ns));
  return (v_pen - reference_pen_mps_).norm() <=
         (o_.max_accel_mps2 + recent_accel_mps2_) * dt_s + difference_noise_mps(o_);
}

void DvlSpikeTest::set_reference(int64_t t_ns, const Eigen::Vector3d& v_pen) {
  const double dt_s = std::abs(seconds_between(reference_ns_, t_ns));
  // The acceleration beyond the noise, from samples close enough in time to show a manoeuvre.
  recent_accel_mps2_ =
      have_reference_ && dt_s > 0 && dt_s <= 1.0
          ? std::max(0.0, (v_pen - reference_pen_mps_).norm() - difference_noise_mps(o_)) / dt_s
          : 0.0;
  have_reference_ = true;
  reference_ns_ = t_ns;
  reference_pen_mps_ = v_pen;
}

std::vector<DvlSample> DvlSpikeTest::push(const DvlSample& s, const Eigen::Vector3d& v_pen) {
  std::vector<DvlSample> released;
  if (!have_reference_ || within_bound(s.timestamp_ns, v_pen)) {
    // Back within the bound: whatever was held was a spike.
    spikes_ += static_cast<int>(held_.size());
    held_.clear();
    set_reference(s.timestamp_ns, v_pen);
    released.push_back(s);
    return released;
  }
  held_.push_back({s, v_pen});
  if (static_cast<int>(held_.size()) <= o_.max_spike_samples) return released;
  // The velocity stayed off for longer than a spike lasts: a manoeuvre. The held samples are
  // released in order and the latest becomes the reference.
  for (const Held& h : held_) {
    set_reference(h.sample.timestamp_ns, h.velocity_pen_mps);
    released.push_back(h.sample);
  }
  held_.clear();
  return released;
}

void DvlSpikeTest::expire(int64_t t_ns) {
  if (held_.empty()) return;
  if (seconds_between(held_.front().sample.timestamp_ns, t_ns) <= o_.max_hold_s) return;
  spikes_ += static_cast<int>(held_.size());
  held_.clear();
}

}  // namespace pensight::global_pose
