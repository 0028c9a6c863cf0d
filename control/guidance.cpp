#include "control/guidance.h"

#include <cmath>

namespace pensight::control {

void LegTracker::advance(double dt_s, double along_m, double depth_m) {
  if (std::isnan(start_depth_m_)) start_depth_m_ = depth_m;
  elapsed_s_ += dt_s;
  along_m_ += std::abs(along_m);
  const Leg& leg = legs_[static_cast<size_t>(index_)];
  const bool last = index_ + 1 == static_cast<int>(legs_.size());
  if (!last && (elapsed_s_ >= leg.duration_s || along_m_ >= leg.length_m)) {
    ++index_;
    elapsed_s_ = 0;
    along_m_ = 0;
    start_depth_m_ = depth_m;
  }
}

Leg LegTracker::current() const {
  Leg leg = legs_[static_cast<size_t>(index_)];
  if (std::isnan(leg.depth_m)) leg.depth_m = start_depth_m_;
  return leg;
}

}  // namespace pensight::control
