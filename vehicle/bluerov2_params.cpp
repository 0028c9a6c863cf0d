#include "vehicle/bluerov2_params.h"

#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/params.h"

namespace pensight::vehicle {
namespace {

constexpr std::string_view kWhere = "vehicle";

// The parameters are built in code, not read from a file: the ranges are those the models need
// (a mass or a rate of 0 divides by zero, a negative damping feeds energy in).
const Param<HullParams> kHullParams[] = {
    {"mass_kg", &HullParams::mass_kg, "kg", kPositive, "dry mass"},
    {"displaced_volume_m3", &HullParams::displaced_volume_m3, "m^3", kPositive,
     "water displaced: buoyancy is its weight"},
    {"water_density_kgpm3", &HullParams::water_density_kgpm3, "kg/m^3", kPositive,
     "sea water 1025; 1007.5 makes the vehicle neutral"},
    {"gravity_mps2", &HullParams::gravity_mps2, "m/s^2", kPositive, "gravitational acceleration"},
};

// The dead band's order against the PWM range is a rule of its own (check_params below); every
// PWM is then above pwm_min_us, so > 0 is what each takes alone.
const Param<T200Params> kT200Params[] = {
    {"pwm_min_us", &T200Params::pwm_min_us, "us", kPositive, "full reverse thrust"},
    {"pwm_max_us", &T200Params::pwm_max_us, "us", kPositive,
     "full forward thrust; above deadband_high_us"},
    {"deadband_low_us", &T200Params::deadband_low_us, "us", kPositive,
     "ESC dead band, low end; above pwm_min_us"},
    {"deadband_high_us", &T200Params::deadband_high_us, "us", kPositive,
     "ESC dead band, high end; at least deadband_low_us"},
    {"max_forward_N", &T200Params::max_forward_N, "N", kPositive, "thrust at pwm_max_us"},
    {"max_reverse_N", &T200Params::max_reverse_N, "N", kPositive, "thrust at pwm_min_us"},
    {"curve_exponent", &T200Params::curve_exponent, "", kPositive,
     "thrust ~ (PWM beyond the dead band)^exponent"},
    {"time_constant_s", &T200Params::time_constant_s, "s", kNonNegative,
     "first-order lag of the thrust behind the PWM (0: none)"},
};

const Param<CurrentParams> kCurrentParams[] = {
    {"variation_mps", &CurrentParams::variation_mps, "m/s", kNonNegative,
     "Gauss-Markov standard deviation per horizontal axis (0: constant current)"},
    {"time_constant_s", &CurrentParams::time_constant_s, "s", kPositive,
     "Gauss-Markov correlation time"},
};

const Param<AutopilotParams> kAutopilotParams[] = {
    {"rate_hz", &AutopilotParams::rate_hz, "Hz", kPositive, "ArduSub's fast loop"},
    {"pilot_gain",
     &AutopilotParams::pilot_gain,
     "",
     {0, 1, true, false},
     "JS_GAIN: the share of the range a full stick asks for"},
    {"max_yaw_rate_radps", &AutopilotParams::max_yaw_rate_radps, "rad/s", kPositive,
     "yaw rate of a full stick at gain 1"},
    {"max_climb_rate_mps", &AutopilotParams::max_climb_rate_mps, "m/s", kPositive,
     "PILOT_SPEED_UP/DN: climb rate of a full throttle stick"},
    {"throttle_deadzone",
     &AutopilotParams::throttle_deadzone,
     "",
     {0, 1, false, true},
     "THR_DZ: share of half the throttle stick that asks for no climb"},
    {"angle_p", &AutopilotParams::angle_p, "1/s", kNonNegative,
     "ATC_ANG_*_P: attitude error to rate"},
    {"depth_p", &AutopilotParams::depth_p, "1/s", kNonNegative, "depth error to climb rate"},
    {"attitude_noise_rad", &AutopilotParams::attitude_noise_rad, "rad", kNonNegative,
     "white noise of the attitude estimate, per axis"},
    {"depth_noise_m", &AutopilotParams::depth_noise_m, "m", kNonNegative,
     "white noise of the pressure sensor's depth"},
};

// A gain's unit is the loop's output per unit of its error, which differs between the loops.
const Param<PidGains> kPidParams[] = {
    {"p", &PidGains::p, "", kNonNegative, "proportional gain"},
    {"i", &PidGains::i, "", kNonNegative, "integral gain, per second"},
    {"d", &PidGains::d, "", kNonNegative, "derivative gain, in seconds"},
    {"imax", &PidGains::imax, "", kNonNegative, "integral clamp, in output units"},
    {"filter_hz", &PidGains::filter_hz, "Hz", kNonNegative,
     "derivative low-pass cut-off (0: unfiltered)"},
};

// The autopilot's PID loops, each checked with kPidParams under "autopilot.KEY.".
struct PidLoop {
  std::string_view key;
  PidGains AutopilotParams::*gains;
};
constexpr PidLoop kPidLoops[] = {
    {"rate_roll_pitch", &AutopilotParams::rate_roll_pitch},
    {"rate_yaw", &AutopilotParams::rate_yaw},
    {"climb_rate", &AutopilotParams::climb_rate},
};

const Param<VehicleParams> kVehicleParams[] = {
    {"physics_rate_hz", &VehicleParams::physics_rate_hz, "Hz", kPositive,
     "RK4 step rate; a whole multiple of autopilot.rate_hz"},
};

// An array of numbers, each element in one range: what a Param (one number) cannot describe.
struct ElementParam {
  std::string_view key;
  std::string_view unit;
  // Of roll, pitch and yaw in a degree-of-freedom array, where it differs from `unit`.
  std::string_view rotation_unit;
  ParamRange range;
  std::string_view help;
};

constexpr ElementParam kInertia{"hull.inertia_kgm2", "kg m^2", "", kPositive,
                                "principal moments of inertia about the centre of gravity"};
constexpr ElementParam kCentreOfBuoyancy{"hull.cb_body_m", "m", "", kAnyNumber,
                                         "centre of buoyancy in B"};
constexpr ElementParam kAddedMass{"hull.added_mass", "kg", "kg m^2", kNonNegative,
                                  "added mass per degree of freedom"};
constexpr ElementParam kLinearDamping{"hull.linear_damping", "N s/m", "N m s", kNonNegative,
                                      "linear damping per degree of freedom"};
constexpr ElementParam kQuadraticDamping{"hull.quadratic_damping", "N s^2/m^2", "N m s^2",
                                         kNonNegative, "quadratic damping per degree of freedom"};
constexpr ElementParam kThrusterPosition{"position_body_m", "m", "", kAnyNumber,
                                         "where the thruster sits in B"};
constexpr ElementParam kMeanCurrent{"current.mean_pen_mps", "m/s", "", kAnyNumber,
                                    "constant part of the current in P"};

[[noreturn]] void fail(const std::string& key, const std::string& what) {
  std::string message(kWhere);
  message.append(": key '").append(key).append("': ").append(what);
  throw Error(message);
}

// name[i]; appends only, which GCC 12's -Wrestrict does not misread as it does a prefix insert.
std::string indexed(std::string_view name, size_t i) {
  std::string key(name);
  return key.append("[").append(std::to_string(i)).append("]");
}

std::string with_unit(double value, std::string_view unit) {
  std::string text = format_param_value(value);
  if (!unit.empty()) text.append(" ").append(unit);
  return text;
}

void check_elements(std::span<const double> values, const ElementParam& p,
                    std::string_view key_prefix = "") {
  for (size_t i = 0; i < values.size(); ++i) {
    if (p.range.contains(values[i])) continue;
    const std::string_view unit = i >= 3 && !p.rotation_unit.empty() ? p.rotation_unit : p.unit;
    fail(indexed(std::string(key_prefix).append(p.key), i),
         param_range_error(values[i], p.range, unit, p.help));
  }
}

void check_elements(const Eigen::Vector3d& values, const ElementParam& p,
                    std::string_view key_prefix = "") {
  check_elements(std::span<const double>(values.data(), 3), p, key_prefix);
}

// key must be above (or, with `or_equal`, at least) the value of other_key; both in `unit`.
void check_order(double value, const std::string& key, double other, std::string_view other_key,
                 bool or_equal, std::string_view unit) {
  if (or_equal ? value >= other : value > other) return;
  std::string what = with_unit(value, unit);
  what.append(or_equal ? " is below " : " is not above ").append(other_key);
  fail(key, what.append(" (").append(with_unit(other, unit)).append(")"));
}

// One Markdown row in param_table_rows' columns.
std::string row(std::string_view key, const std::string& defaults, std::string_view unit,
                const std::string& valid, std::string_view help) {
  std::string r = "| `";
  r.append(key).append("` | ").append(defaults).append(" | ").append(unit).append(" | ");
  return r.append(valid).append(" | ").append(help).append(" |\n");
}

std::string element_row(const ElementParam& p, const std::string& defaults,
                        std::string_view key_prefix = "") {
  std::string unit(p.unit);
  if (!p.rotation_unit.empty()) unit.append(", ").append(p.rotation_unit);
  return row(std::string(key_prefix).append(p.key).append("[]"), defaults, unit, p.range.text(),
             p.help);
}

std::string joined(std::span<const double> values) {
  std::string text;
  for (const double v : values) text.append(text.empty() ? "" : ", ").append(format_param_value(v));
  return text;
}

std::string joined(const Eigen::Vector3d& values) {
  return joined(std::span<const double>(values.data(), 3));
}

std::string prefixed(std::string_view prefix, std::string_view key) {
  return std::string(prefix).append(key).append(".");
}

}  // namespace

ThrusterLayout bluerov2_heavy_layout() {
  const double c = std::numbers::sqrt2 / 2;
  const Eigen::Vector3d down = Eigen::Vector3d::UnitZ();
  return {{{{0.156, 0.111, 0.085}, {-c, c, 0}},
           {{0.156, -0.111, 0.085}, {-c, -c, 0}},
           {{-0.156, 0.111, 0.085}, {c, c, 0}},
           {{-0.156, -0.111, 0.085}, {c, -c, 0}},
           {{0.120, 0.218, 0.0}, down},
           {{0.120, -0.218, 0.0}, down},
           {{-0.120, 0.218, 0.0}, down},
           {{-0.120, -0.218, 0.0}, down}}};
}

void check_params(const VehicleParams& p) {
  const HullParams& h = p.hull;
  pensight::check_params<HullParams>(h, kHullParams, kWhere, "hull.");
  check_elements(h.inertia_kgm2, kInertia);
  check_elements(h.cb_body_m, kCentreOfBuoyancy);
  check_elements(h.added_mass, kAddedMass);
  check_elements(h.linear_damping, kLinearDamping);
  check_elements(h.quadratic_damping, kQuadraticDamping);

  for (size_t i = 0; i < p.thrusters.size(); ++i) {
    const std::string thruster = indexed("thrusters", i).append(".");
    check_elements(p.thrusters[i].position_body_m, kThrusterPosition, thruster);
    const double norm = p.thrusters[i].direction_body.norm();
    if (!(std::abs(norm - 1) < 1e-6)) {
      std::string what = "its norm ";
      fail(thruster + "direction_body",
           what.append(format_param_value(norm)).append(" is not 1 (a unit vector)"));
    }
  }

  const T200Params& t = p.t200;
  pensight::check_params<T200Params>(t, kT200Params, kWhere, "t200.");
  check_order(t.deadband_low_us, "t200.deadband_low_us", t.pwm_min_us, "t200.pwm_min_us", false,
              "us");
  check_order(t.deadband_high_us, "t200.deadband_high_us", t.deadband_low_us,
              "t200.deadband_low_us", true, "us");
  check_order(t.pwm_max_us, "t200.pwm_max_us", t.deadband_high_us, "t200.deadband_high_us", false,
              "us");

  pensight::check_params<CurrentParams>(p.current, kCurrentParams, kWhere, "current.");
  check_elements(p.current.mean_pen_mps, kMeanCurrent);

  const AutopilotParams& a = p.autopilot;
  pensight::check_params<AutopilotParams>(a, kAutopilotParams, kWhere, "autopilot.");
  for (const PidLoop& loop : kPidLoops) {
    pensight::check_params<PidGains>(a.*loop.gains, kPidParams, kWhere,
                                     prefixed("autopilot.", loop.key));
  }

  pensight::check_params<VehicleParams>(p, kVehicleParams, kWhere);
  const double ratio = p.physics_rate_hz / a.rate_hz;
  if (!(ratio >= 1 && std::abs(ratio - std::round(ratio)) < 1e-9 * ratio)) {
    std::string what = with_unit(p.physics_rate_hz, "Hz");
    what.append(" is not a whole multiple of autopilot.rate_hz (");
    fail("physics_rate_hz", what.append(with_unit(a.rate_hz, "Hz")).append(")"));
  }
}

std::string bluerov2_param_rows() {
  const VehicleParams d;
  std::string rows = param_table_rows<HullParams>(kHullParams, d.hull, "hull.");
  rows += element_row(kInertia, joined(d.hull.inertia_kgm2));
  rows += element_row(kCentreOfBuoyancy, joined(d.hull.cb_body_m));
  rows += element_row(kAddedMass, joined(d.hull.added_mass));
  rows += element_row(kLinearDamping, joined(d.hull.linear_damping));
  rows += element_row(kQuadraticDamping, joined(d.hull.quadratic_damping));
  rows += element_row(kThrusterPosition, "ArduSub VECTORED_6DOF", "thrusters[].");
  rows += row("thrusters[].direction_body", "ArduSub VECTORED_6DOF", "", "norm 1",
              "the way the thruster pushes at a PWM above 1500 us");
  rows += param_table_rows<T200Params>(kT200Params, d.t200, "t200.");
  rows += param_table_rows<CurrentParams>(kCurrentParams, d.current, "current.");
  rows += element_row(kMeanCurrent, joined(d.current.mean_pen_mps));
  rows += param_table_rows<AutopilotParams>(kAutopilotParams, d.autopilot, "autopilot.");
  for (const PidLoop& loop : kPidLoops) {
    rows += param_table_rows<PidGains>(kPidParams, d.autopilot.*loop.gains,
                                       prefixed("autopilot.", loop.key));
  }
  rows += param_table_rows<VehicleParams>(kVehicleParams, d);
  return rows;
}

}  // namespace pensight::vehicle
