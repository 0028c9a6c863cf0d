#include "pipeline/global_pose/motion_schedule.h"

namespace pensight::global_pose {

std::optional<int64_t> MotionSchedule::add(int64_t t_ns, const Eigen::Vector3d& v_pen) {
  if (!spans_.empty() && t_ns <= spans_.rbegin()->first) return std::nullopt;
  std::optional<int64_t> reapply_from;
  if (spans_.empty()) {
    spans_[t_ns] = {t_ns, false};
  } else {
    const auto& [last_ns, last] = *spans_.rbegin();
    const double dt_s = seconds_between(last_ns, t_ns);
    const bool within = dt_s <= o_.max_hold_s &&
                        (v_pen - last_velocity_pen_mps_).norm() <=
                            o_.max_accel_mps2 * dt_s + DvlSpikeTest::difference_noise_mps(o_);
    if (!within) calm_since_ns_ = kNotCalm;
    if (within && calm_since_ns_ == kNotCalm) calm_since_ns_ = last_ns;
    const bool quiet = within && seconds_between(calm_since_ns_, t_ns) >= settle_s_;
    // While it went on, the span was predicted as quiet up to due_ns when the one before was
    // quiet, as manoeuvring after it; re-apply it where that differs from what it was.
    const bool predicted_quiet = last.quiet && t_ns <= due_ns(last_ns, last);
    if ((quiet && !predicted_quiet) || (!quiet && last.quiet)) reapply_from = last_ns;
    spans_[t_ns] = {last_ns, quiet};
  }
  last_velocity_pen_mps_ = v_pen;
  return reapply_from;
}

bool MotionSchedule::quiet(int64_t t0_ns, int64_t t1_ns) const {
  if (spans_.empty()) return false;
  const auto it = spans_.lower_bound(t1_ns);
  if (it != spans_.end()) return it->second.quiet && it->second.start_ns <= t0_ns;
  // After the latest sample: as quiet as its span until the next sample is due. An overdue
  // sample may be held by the spike test because the vehicle is manoeuvring.
  const auto& [last_ns, last] = *spans_.rbegin();
  return last.quiet && t1_ns <= due_ns(last_ns, last);
}

int64_t MotionSchedule::due_ns(int64_t end_ns, const Span& span) {
  return end_ns + (end_ns - span.start_ns) * 3 / 2;
}

void MotionSchedule::trim_before(int64_t t_ns) {
  while (spans_.size() > 1 && spans_.begin()->first < t_ns) spans_.erase(spans_.begin());
}

}  // namespace pensight::global_pose
