#pragma once
// What the net-relative controller is told (docs/control.md gives every key with its unit): the
// guidance legs, the loops' gains and limits, the velocity strategy, the safety timings and the
// controller's model of the vehicle (feed-forward and stick scaling). Defaults are the published
// framework's gains (Amundsen et al. 2022 guidance; BlueROV2 Heavy on ArduSub in depth hold).
#include <limits>
#include <string>
#include <vector>

#include "control/pid.h"
#include "core/strict_yaml.h"
#include "core/units.h"
#include "vehicle/bluerov2_params.h"

namespace pensight::control {

// How the vehicle's speed along and across its body axes is made:
// kDvlFeedback (a): a velocity loop on the DVL's body velocity around the feed-forward force;
// kOpenLoop (b): the feed-forward force alone, a constant thrust (PWM) per commanded speed.
enum class VelocityStrategy { kDvlFeedback, kOpenLoop };
const char* to_string(VelocityStrategy s);

// One leg of the mission: hold `d_ref_m` from the net, face it at `heading_ref_rad` (net-relative:
// 0 = squarely, > 0 = turned right, as psi_net), move along it at `sway_speed_mps` (> 0: to the
// right), at `depth_m` (NaN: the depth at the leg's start). A leg ends after `duration_s` or once
// `length_m` has been travelled along the net, whichever comes first; the last leg never ends.
struct Leg {
  double d_ref_m = 1.0;
  double heading_ref_rad = 0;
  double sway_speed_mps = 0;
  double depth_m = kNaN;
  double duration_s = std::numeric_limits<double>::infinity();
  double length_m = std::numeric_limits<double>::infinity();
};

struct LoopGains {
  // x: distance error d_net - d_ref [m] -> surge speed reference u_ref [m/s].
  PidGains surge_position{3.0, 0.0, 0.3};
  // u: surge speed error u_ref - u_dvl [m/s] -> surge force [N], around the feed-forward.
  PidGains surge_velocity{10.0, 1.0, 0.0};
  // y: along-net position error [m] -> sway force [N], around the feed-forward F(v_ref): the
  // reference moves at the leg's speed, the position is the DVL's sway integrated, so the speed
  // along the net comes out right whatever force a current or the thrusters' dead band add.
  PidGains sway_position{30.0, 0.001, 0.0};
  // yaw: heading error psi_net - heading_ref [deg] -> yaw-rate demand [rad/s].
  PidGains yaw{0.075, 0.007, 0.008};
};

struct LoopLimits {
  double surge_speed_mps = 0.25;    // |u_ref|
  double sway_speed_mps = 0.3;      // |v_ref| a leg may ask for
  double yaw_rate_radps = 0.35;     // |r_ref|
  double climb_rate_mps = 0.2;      // depth changes
  double depth_gain_per_s = 0.5;    // climb-rate demand per metre of depth error
  double force_rate_n_per_s = 200;  // thrust ramps, per horizontal axis
};

// The controller's model of the vehicle. The surge and sway damping give the feed-forward force
// F(v) = linear v + quadratic v |v|; with the masses they carry the DVL's velocity forward between
// its samples (4 Hz against the 10 Hz loops). The rest is what a stick does on ArduSub in
// ALT_HOLD: x and y are scaled by the pilot gain into a motor output in [-1, 1] (PWM 1500 + 400
// output) of the four vectored thrusters at 45 deg, which push as a T200 does (no thrust in the
// ESC's dead band, a power law beyond); r asks for a yaw rate, z for a climb rate (stick_map.h
// inverts this for the thrust a loop wants). The defaults are the published BlueROV2 Heavy and
// ArduSub values the vehicle layer holds (vehicle/bluerov2_params.h); a real vehicle's may
// differ, which is why the controller has its own copy.
struct VehicleModel {
  double surge_mass_kg = kHull.mass_kg + kHull.added_mass[0];
  double sway_mass_kg = kHull.mass_kg + kHull.added_mass[1];
  double surge_damping_linear = kHull.linear_damping[0];
  double surge_damping_quadratic = kHull.quadratic_damping[0];
  double sway_damping_linear = kHull.linear_damping[1];
  double sway_damping_quadratic = kHull.quadratic_damping[1];
  double pilot_gain = kAutopilot.pilot_gain;
  double deadband_low_us = kT200.deadband_low_us, deadband_high_us = kT200.deadband_high_us;
  double max_forward_n = kT200.max_forward_N, max_reverse_n = kT200.max_reverse_N;  // 1900/1100 us
  double thrust_exponent = kT200.curve_exponent;
  // ACRO_YAW_P 3.375 x 45 deg/s x the pilot gain, to 4 digits (the vehicle layer: 1.32536).
  double full_stick_yaw_rate_radps = 1.325;
  double full_stick_climb_rate_mps = kAutopilot.max_climb_rate_mps;

 private:
  static inline const vehicle::HullParams kHull{};
  static inline const vehicle::T200Params kT200{};
  static inline const vehicle::AutopilotParams kAutopilot{};
};

struct SafetyConfig {
  double startup_s = 2.0;           // armed, depth hold, held still before the first leg
  double pose_timeout_s = 0.5;      // no valid relative pose for this long: hold
  double backoff_after_s = 3.0;     // no valid pose for this long: back away from the net
  double backoff_speed_mps = 0.05;  // slowly, so a net that reappears is not lost again
  double backoff_max_m = 1.0;       // then hold again
  double dvl_timeout_s = 1.0;       // no DVL sample for this long: the open-loop strategy
  // A DVL sample this far from the observer's velocity is a spike and is dropped, unless the
  // next one agrees with it (then the model was wrong, not the DVL).
  double dvl_gate_mps = 0.15;
};

struct ControlConfig {
  VelocityStrategy strategy = VelocityStrategy::kDvlFeedback;
  std::vector<Leg> legs{Leg{}};  // at least one
  LoopGains gains;
  LoopLimits limits;
  VehicleModel vehicle;
  SafetyConfig safety;
};

// Reads a `control:` mapping (a scenario's section or a file of its own) strictly: a typo names
// the key; a negative or non-finite gain or limit, a loop that cannot act (surge_position.kp or
// yaw.kp of 0), no legs, or a leg with d_ref_m <= 0 or a speed beyond the limit throws
// pensight::Error naming the file and key.
ControlConfig parse_control_config(const YamlMap& map);
ControlConfig load_control_config(const std::string& file);
// Throws like parse_control_config for a config built in code; messages read
// "FILE: key 'PREFIXgains.yaw.kp': ..." (key_prefix: "control." for a scenario's section).
void validate(const ControlConfig& c, const std::string& file, const std::string& key_prefix = "");
// Every key of a `control:` mapping with its default, unit, valid range and help: the rows of a
// Markdown table under core/params.h's kParamTableHeader (docs/parameters.md).
std::string control_param_rows();

}  // namespace pensight::control
