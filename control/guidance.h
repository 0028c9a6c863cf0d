#pragma once
// Net-relative guidance (after Amundsen et al. 2022): the mission as legs of (distance to keep,
// heading to the net, speed along it, depth) that end after a time or a length travelled along the
// net. A lawnmower is legs alternating the sway direction; a hold is one leg at zero speed.
#include <vector>

#include "control/control_config.h"
#include "core/units.h"

namespace pensight::control {

class LegTracker {
 public:
  // `legs` as validated by validate(ControlConfig).
  explicit LegTracker(std::vector<Leg> legs) : legs_(std::move(legs)) {}

  // Advances the current leg by `dt_s` during which the vehicle moved `along_m` along the net
  // (signed; the DVL's sway, or the commanded speed without one), then moves on to the next leg
  // when this one has lasted its duration or covered its length. `depth_m`: the vehicle's depth
  // now, which a leg without a depth keeps from its start.
  void advance(double dt_s, double along_m, double depth_m);
  // The current leg with its depth resolved (NaN until a depth was seen).
  Leg current() const;
  int index() const { return index_; }

 private:
  std::vector<Leg> legs_;
  int index_ = 0;
  double elapsed_s_ = 0, along_m_ = 0;
  double start_depth_m_ = kNaN;
};

}  // namespace pensight::control
