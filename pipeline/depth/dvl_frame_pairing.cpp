#include "pipeline/depth/dvl_frame_pairing.h"

#include <cmath>

namespace pensight {

void DvlFramePairing::add(const DvlSample& s) {
  const auto max_dt_ns = static_cast<int64_t>(max_pair_dt_s_ * 1e9);
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
    const double dt_s = 1e-9 * static_cast<double>(t_frame_ns - s.timestamp_ns);
    if (dt_s <= max_pair_dt_s_) paired.push_back({s, dt_s});
  }
  pending_ = std::move(later);
  return paired;
}

}  // namespace pensight
