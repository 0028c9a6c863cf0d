#pragma once
// ArduSub's manual-control modes, as the published BlueROV2 runs flew them (ALT_HOLD), reduced to
// their structure: pilot sticks scaled by the joystick gain (joystick.cpp); roll and pitch held
// level and yaw rate or heading held by angle P and rate PID loops (AC_AttitudeControl_Sub); in
// ALT_HOLD the depth held by a position P and a climb-rate PI whose integral carries the buoyancy
// (mode_althold.cpp, get_pilot_desired_climb_rate); the result mixed into PWMs
// (mix_vectored_6dof). It reads the true state through white attitude and depth noise.
#include <random>

#include "vehicle/bluerov2_params.h"
#include "vehicle/hull_dynamics.h"
#include "vehicle/thrusters.h"

namespace pensight::vehicle {

enum class FlightMode { kManual, kStabilize, kAltHold };

// MAVLink MANUAL_CONTROL scaled to sticks, plus the mode and arming a companion computer sets.
struct ManualCommand {
  double x = 0;    // forward, [-1, 1]
  double y = 0;    // lateral (right), [-1, 1]
  double z = 0.5;  // throttle, [0, 1]: 0.5 holds, above climbs
  double r = 0;    // yaw (right), [-1, 1]
  FlightMode mode = FlightMode::kAltHold;
  bool armed = false;
};

class ArduSubAutopilot {
 public:
  // Precondition: check_params() accepted the autopilot.
  explicit ArduSubAutopilot(const AutopilotParams& params);

  // One loop of 1 / rate_hz: the eight PWMs (us), all 1500 while disarmed. Sticks outside their
  // range are clamped. Arming or a mode change takes the current heading and depth as targets
  // and empties the integrators.
  ThrusterVector update(const ManualCommand& command, const RigidBodyState& truth);

 private:
  struct PidState {
    double integral = 0, previous_error = 0, derivative = 0;
    bool started = false;
  };
  double run_pid(const PidGains& gains, PidState& state, double error) const;
  double hold_depth(double throttle_stick, double depth_m, double climb_mps);

  AutopilotParams params_;
  double dt_s_;
  std::mt19937_64 rng_;
  bool engaged_ = false;
  FlightMode mode_ = FlightMode::kManual;
  double heading_target_rad_ = 0;
  double depth_target_m_ = 0;
  double since_yaw_input_s_ = 0;
  PidState roll_, pitch_, yaw_, climb_;
};

}  // namespace pensight::vehicle
