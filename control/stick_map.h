#pragma once
// Sticks and thrust on ArduSub in ALT_HOLD, as the controller models them (VehicleModel): the
// horizontal force the surge and sway sticks make together, and its inverse. The model is the
// vehicle layer's (vehicle/thrusters.h: ArduSub's VECTORED_6DOF mixing, the T200 curve, the
// BlueROV2 Heavy's thruster layout) with the controller's own parameters, because the sticks
// share the four vectored thrusters: each runs x +- y, so with the T200's dead band and curve a
// sway stick alone and the same stick beside a surge stick push differently (a 0.1 m/s sway
// demand beside the surge loop's stick came out at 0.15-0.17 m/s when the axes were inverted one
// by one).
#include <Eigen/Core>

#include "control/control_config.h"

namespace pensight::control {

// The force (N) along body x and y at sticks (x, y), each in [-1, 1] (clamped): the sticks times
// the pilot gain are the mixer's forward and lateral demands, the PWMs give each thruster's
// thrust, the allocation sums them. Yaw and the vertical thrusters are left out.
Eigen::Vector2d horizontal_force_n(const VehicleModel& m, double x, double y);

// The sticks for a force (N, body x and y), scaled down to what the vehicle can push: each pair
// of thrusters on a diagonal pushes along it with a force of x + y or x - y alone, so the two
// diagonal forces are inverted separately by bisection (~80 force evaluations, ~10 us); the
// result makes the force to 1e-6 N. Below 0.5 N a diagonal's share falls linearly to 0 from the
// one that makes 0.5 N, so that noise about zero force does not flip its thrusters from one edge
// of the dead band to the other. Precondition: the pilot gain keeps |x +- y| times it within 1
// (the mixer does not rescale), true for gain <= 0.5.
Eigen::Vector2d sticks_for_horizontal_force(const VehicleModel& m, const Eigen::Vector2d& force_n);

// The largest force one axis reaches alone (full stick).
double full_stick_force_n(const VehicleModel& m);

}  // namespace pensight::control
