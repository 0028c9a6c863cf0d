#pragma once
// The eight T200s: thrust from PWM, the allocation matrix tau = B f, and ArduSub's mixing of axis
// demands into PWMs for the VECTORED_6DOF frame.
#include <Eigen/Core>

#include "vehicle/bluerov2_params.h"

namespace pensight::vehicle {

using AllocationMatrix = Eigen::Matrix<double, 6, kThrusterCount>;

// Static thrust (N, along the mount direction) at a PWM, clamped to [pwm_min_us, pwm_max_us]:
// zero inside the dead band, max * (distance from the band / its span)^exponent outside.
// Continuous and non-decreasing in the PWM.
double t200_thrust_N(const T200Params& t200, double pwm_us);

// Columns [d_i; r_i x d_i] (Fossen 2011, control allocation): force and moment in B per newton of
// thrust.
AllocationMatrix allocation_matrix(const ThrusterLayout& layout);

// What ArduSub's attitude and position controllers ask of the motors, each in [-1, 1]: roll right,
// pitch up, yaw right, throttle up, forward, lateral right.
struct AxisDemand {
  double roll = 0, pitch = 0, yaw = 0, throttle = 0, forward = 0, lateral = 0;
};

// AP_Motors6DOF::output_armed_stabilizing_vectored_6dof: each motor gets its factor-weighted sum
// of the demands; roll, pitch and throttle (the vertical motors) and yaw, forward and lateral
// (the horizontal ones) are each scaled down together when a motor would exceed 1, then PWM =
// 1500 + 400 output.
ThrusterVector mix_vectored_6dof(const AxisDemand& demand);

}  // namespace pensight::vehicle
