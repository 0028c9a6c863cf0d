#include "pipeline/global_pose/attitude_series.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"

namespace pensight::global_pose {
namespace {
bool earlier(const AttitudeSample& a, int64_t t) {
  return a.timestamp_ns < t;
}
}  // namespace

bool AttitudeSeries::insert(const AttitudeSample& s) {
  if (!std::isfinite(s.roll_rad) || !std::isfinite(s.pitch_rad)) return false;
  const auto it = std::lower_bound(samples_.begin(), samples_.end(), s.timestamp_ns, earlier);
  if (it != samples_.end() && it->timestamp_ns == s.timestamp_ns) return false;
  samples_.insert(it, s);
  return true;
}

std::optional<AttitudeSample> AttitudeSeries::at(int64_t t_ns, double max_gap_s) const {
  if (samples_.empty()) return std::nullopt;
  const auto max_gap_ns = seconds_to_ns_toward_zero(max_gap_s);
  const auto hi = std::lower_bound(samples_.begin(), samples_.end(), t_ns, earlier);
  if (hi == samples_.end()) {
    const AttitudeSample& last = samples_.back();
    if (t_ns - last.timestamp_ns > max_gap_ns) return std::nullopt;
    return last;
  }
  if (hi->timestamp_ns == t_ns || hi == samples_.begin()) {
    if (hi->timestamp_ns - t_ns > max_gap_ns) return std::nullopt;
    return *hi;
  }
  const AttitudeSample& a = *(hi - 1);
  const AttitudeSample& b = *hi;
  if (b.timestamp_ns - a.timestamp_ns > 2 * max_gap_ns) {
    const AttitudeSample& near = (t_ns - a.timestamp_ns < b.timestamp_ns - t_ns) ? a : b;
    if (std::abs(near.timestamp_ns - t_ns) > max_gap_ns) return std::nullopt;
    return near;
  }
  const double f = static_cast<double>(t_ns - a.timestamp_ns) /
                   static_cast<double>(b.timestamp_ns - a.timestamp_ns);
  AttitudeSample s;
  s.timestamp_ns = t_ns;
  s.roll_rad = a.roll_rad + f * (b.roll_rad - a.roll_rad);
  s.pitch_rad = a.pitch_rad + f * (b.pitch_rad - a.pitch_rad);
  s.yaw_rad = wrap_angle(a.yaw_rad + f * wrap_angle(b.yaw_rad - a.yaw_rad));
  return s;
}

std::optional<double> AttitudeSeries::yaw_rate(int64_t t_ns, double window_s) const {
  const int64_t from_ns = t_ns - seconds_to_ns_toward_zero(window_s);
  auto it = std::lower_bound(samples_.begin(), samples_.end(), from_ns, earlier);
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0, yaw = 0, previous = 0;
  for (; it != samples_.end() && it->timestamp_ns <= t_ns; ++it) {
    if (!std::isfinite(it->yaw_rad)) return std::nullopt;
    yaw = n == 0 ? 0.0 : yaw + wrap_angle(it->yaw_rad - previous);
    previous = it->yaw_rad;
    const double t = seconds_between(from_ns, it->timestamp_ns);
    n += 1;
    st += t;
    sy += yaw;
    stt += t * t;
    sty += t * yaw;
  }
  const double det = n * stt - st * st;
  if (n < 3 || !(det > 0)) return std::nullopt;
  return (n * sty - st * sy) / det;
}

void AttitudeSeries::trim_before(int64_t t_ns) {
  while (samples_.size() > 1 && samples_[1].timestamp_ns < t_ns) samples_.pop_front();
}

}  // namespace pensight::global_pose
