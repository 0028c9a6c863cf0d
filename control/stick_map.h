#pragma once
// Sticks and thrust on ArduSub in ALT_HOLD, as the controller models them (VehicleModel): the
// horizontal force a surge or sway stick makes, and its inverse, which compensates the T200's dead
// band so that a loop asking for a small force gets one.
#include "control/control_config.h"

namespace pensight::control {

// The force (N) along the body x (surge) or y (sway) axis at stick s in [-1, 1] (clamped): the
// stick times the pilot gain is every vectored motor's output o (PWM 1500 +- 400 o); two run
// forward and two in reverse, each at 45 deg to the axis. Odd and non-decreasing in s; 0 while the
// PWMs stay in the dead band.
double axis_force_n(const VehicleModel& m, double stick);

// The stick for `force_n` (clamped to the axis's reach): the smallest that makes the force, found
// by bisection (40 halvings; ~2 us). Below 0.5 N the stick falls linearly to 0 from the edge of
// the dead band, so that noise about zero force does not flip the thrusters from one edge to the
// other.
double stick_for_axis_force(const VehicleModel& m, double force_n);

}  // namespace pensight::control
