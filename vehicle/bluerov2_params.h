#pragma once
// Parameters of the BlueROV2 Heavy simulator, with published values as defaults. Body frame B is
// FRD with its origin at the centre of gravity; pen frame P is z down with its origin at the water
// surface (docs/conventions.md). Hydrodynamic coefficients are positive magnitudes: Fossen (2011,
// Handbook of Marine Craft Hydrodynamics and Motion Control) writes them as negative derivatives,
// X_u = -13.7. Degree-of-freedom arrays are ordered surge, sway, heave, roll, pitch, yaw.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>

#include "core/units.h"

namespace pensight::vehicle {

using Vector6d = Eigen::Matrix<double, 6, 1>;
inline constexpr int kThrusterCount = 8;
using ThrusterVector = Eigen::Matrix<double, kThrusterCount, 1>;
inline constexpr double kKgf_N = 9.80665;

// Hull and hydrodynamics: von Benzon et al. 2022, "An Open-Source Benchmark Simulator: Control of
// a BlueROV2 Underwater Robot", JMSE 10(12):1898, Table 1.
struct HullParams {
  double mass_kg = 13.5;
  double displaced_volume_m3 = 0.0134;
  // Sea water: buoyancy (134.7 N) exceeds weight (132.4 N), the slight positive trim of a real
  // BlueROV2. 1007.5 makes the vehicle neutral.
  double water_density_kgpm3 = 1025.0;
  double gravity_mps2 = 9.81;
  Eigen::Vector3d inertia_kgm2{0.26, 0.23, 0.37};  // principal, about the centre of gravity
  Eigen::Vector3d cb_body_m{0.0, 0.0, -0.01};      // centre of buoyancy: above the CG
  std::array<double, 6> added_mass = {6.36, 7.12, 18.69, 0.186, 0.135, 0.222};  // kg, kg m^2
  std::array<double, 6> linear_damping = {13.7, 0.0, 33.0, 0.0, 0.8, 0.0};      // N s/m, N m s
  std::array<double, 6> quadratic_damping = {141.0, 217.0, 190.0, 1.19, 0.47, 1.50};
};

// Where a thruster sits and which way it pushes the vehicle when its PWM is above 1500 us.
struct ThrusterMount {
  Eigen::Vector3d position_body_m;
  Eigen::Vector3d direction_body;  // unit
};
using ThrusterLayout = std::array<ThrusterMount, kThrusterCount>;

// ArduSub's VECTORED_6DOF frame (ArduPilot libraries/AP_Motors/AP_Motors6DOF.cpp): motors 1-4
// horizontal at 45 deg (front right, front left, rear right, rear left), 5-8 vertical (same
// order), each pushing the way its motor factors ask for a positive output; the vertical ones push
// down, so climbing runs them in reverse. Positions: von Benzon et al. 2022's thrust allocation.
ThrusterLayout bluerov2_heavy_layout();

// Blue Robotics T200 at 14 V: no thrust inside the ESC's dead band, outside it the thrust grows as
// a power of the PWM's distance from the band, reaching the maximum at the end of the range. The
// exponent 1.35 follows Blue Robotics' published data: 0.39 of full thrust at half the travel,
// where a square gives 0.25.
struct T200Params {
  double pwm_min_us = 1100.0;
  double pwm_max_us = 1900.0;
  double deadband_low_us = 1464.0;
  double deadband_high_us = 1532.0;
  double max_forward_N = 4.52 * kKgf_N;  // at pwm_max_us
  double max_reverse_N = 3.52 * kKgf_N;  // at pwm_min_us
  double curve_exponent = 1.35;
  double time_constant_s = 0.1;  // first-order lag of the thrust behind the PWM
};

// Ocean current in P: a constant plus a first-order Gauss-Markov variation of the horizontal
// components (Fossen 2011, ch. 8), started from its stationary distribution.
struct CurrentParams {
  Eigen::Vector3d mean_pen_mps = Eigen::Vector3d::Zero();
  double variation_mps = 0.0;  // stationary standard deviation per horizontal axis
  double time_constant_s = 60.0;
  uint64_t seed = 1;
};

// ArduPilot AC_PID: output = P e + I integral(e) (clamped to +-imax) + D de/dt (low-passed).
struct PidGains {
  double p = 0, i = 0, d = 0, imax = 0, filter_hz = 0;
};

// ArduSub's manual-control modes. Defaults are ArduSub's (ArduSub/config.h, joystick.cpp and
// AC_AttitudeControl_Sub.h) except where a comment says otherwise.
struct AutopilotParams {
  double rate_hz = 400.0;   // the fast loop
  double pilot_gain = 0.5;  // JS_GAIN_DEFAULT: full stick asks for half of the range
  // Full yaw stick at gain 1: ACRO_YAW_P (3.375) x 45 deg/s.
  double max_yaw_rate_radps = deg_to_rad(3.375 * 45.0);
  // PILOT_SPEED_UP/DN: ArduSub's 5 m/s default is beyond the vehicle, which tops out near 0.8 m/s.
  double max_climb_rate_mps = 0.5;
  double throttle_deadzone = 0.2;  // THR_DZ 100 of the 0..1000 throttle: a fifth of half a stick
  double angle_p = 6.0;            // ATC_ANG_*_P, 1/s
  // Rate loops (output per rad/s) tuned on this model: ArduSub's P 0.135, I 0.09 (roll, pitch)
  // and P 0.18, I 0.018 (yaw) stay inside the T200 dead band too long here, pitching 21 deg when
  // a full surge starts and reaching half the asked yaw rate after 8 s.
  PidGains rate_roll_pitch{0.6, 0.5, 0.0036, 0.444, 30.0};
  PidGains rate_yaw{0.5, 0.5, 0.0, 0.222, 5.0};
  // Depth hold, tuned on this model: position P (1/s) to a climb rate, a climb-rate PI to
  // throttle whose integral carries the buoyancy.
  double depth_p = 1.0;
  PidGains climb_rate{1.0, 1.0, 0.0, 0.5, 0.0};
  double attitude_noise_rad = deg_to_rad(0.05);  // per axis, white
  double depth_noise_m = 0.002;                  // pressure sensor, white
  uint64_t noise_seed = 2;
};

struct VehicleParams {
  HullParams hull;
  ThrusterLayout thrusters = bluerov2_heavy_layout();
  T200Params t200;
  CurrentParams current;
  AutopilotParams autopilot;
  double physics_rate_hz = 400.0;  // RK4 step; autopilot.rate_hz divides it
};

// Throws pensight::Error "vehicle: key 'PATH': ..." for the first parameter out of its range
// ("hull.mass_kg: -1 is outside > 0 kg (...)") or breaking a rule that ties it to another (the
// dead band inside the PWM range, the physics rate a whole multiple of the autopilot's).
void check_params(const VehicleParams& params);

// Markdown rows (core/params.h's param_table_rows) of every parameter check_params checks, keys
// as in its messages ("hull.mass_kg", "hull.added_mass[]"), defaults those of VehicleParams{}.
std::string bluerov2_param_rows();

}  // namespace pensight::vehicle
