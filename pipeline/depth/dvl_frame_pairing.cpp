#include "pipeline/depth/dvl_frame_pairing.h"

#include <cmath>

#include "core/units.h"

namespace pensight {

void DvlFramePairing::add(const DvlSample& s) {
  const auto max_dt_ns = seconds_to_ns_toward_zero(max_pair_dt_s_);
  std::erase_if(pending_,
                [&](const DvlSample& p) { return p.timestamp_ns < s.timestamp_ns - max_dt_ns; });
  pending_.push_back(s);
}

std::vector<DvlFramePairing::Paired> DvlFramePairing::take(int64_t t_frame_ns) {
  std::vector<Paired> paired;
  std::vector<DvlSample> later;
  for (const DvlSample& s : pending_) {
    if (s.timestamp_ns > t_frame_ns) {
      later.push_back(s);
      continue;
    }
    const double dt_s = seconds_between(s.timestamp_ns, t_frame_ns);
    if (dt_s <= max_pair_dt_s_) paired.push_back({s, dt_s});
  }
  pending_ = std::move(later);
  return paired;
}

}  // namespace pensight
