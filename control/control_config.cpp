#include "control/control_config.h"

#include <cmath>
#include <string_view>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/params.h"
#include "core/strict_yaml.h"

namespace pensight::control {

namespace {

constexpr EnumName<VelocityStrategy> kStrategyNames[] = {
    {VelocityStrategy::kDvlFeedback, "dvl"},
    {VelocityStrategy::kOpenLoop, "open_loop"},
};

}  // namespace

const char* to_string(VelocityStrategy s) {
  return enum_name<VelocityStrategy>(kStrategyNames, s);
}

namespace {

const Param<PidGains> kGainParams[] = {
    {"kp", &PidGains::kp, "", kNonNegative,
     "proportional gain (the loop's sign is the controller's)"},
    {"ki", &PidGains::ki, "", kNonNegative, "integral gain, per second"},
    {"kd", &PidGains::kd, "", kNonNegative, "derivative gain, in seconds"},
};

const Param<LoopLimits> kLimitParams[] = {
    {"surge_speed_mps", &LoopLimits::surge_speed_mps, "m/s", kPositive,
     "largest surge speed reference"},
    {"sway_speed_mps", &LoopLimits::sway_speed_mps, "m/s", kPositive,
     "largest sway speed a leg may ask for"},
    {"yaw_rate_radps", &LoopLimits::yaw_rate_radps, "rad/s", kPositive,
     "largest yaw-rate reference"},
    {"climb_rate_mps", &LoopLimits::climb_rate_mps, "m/s", kPositive, "depth changes"},
    {"depth_gain_per_s", &LoopLimits::depth_gain_per_s, "1/s", kPositive,
     "climb-rate demand per metre of depth error"},
    {"force_rate_n_per_s", &LoopLimits::force_rate_n_per_s, "N/s", kPositive,
     "thrust ramp per horizontal axis"},
};

// ArduSub's ESC output spans 1100-1900 us around 1500 us neutral; above a pilot gain of 0.5 it
// rescales a combined surge and sway stick, which the stick model (stick_map.h) does not.
const Param<VehicleModel> kVehicleParams[] = {
    {"surge_mass_kg", &VehicleModel::surge_mass_kg, "kg", kPositive, "mass + added mass, surge"},
    {"sway_mass_kg", &VehicleModel::sway_mass_kg, "kg", kPositive, "mass + added mass, sway"},
    {"surge_damping_linear", &VehicleModel::surge_damping_linear, "N s/m", kNonNegative,
     "feed-forward F(u), linear term"},
    {"surge_damping_quadratic", &VehicleModel::surge_damping_quadratic, "N s^2/m^2", kNonNegative,
     "feed-forward F(u), quadratic term"},
    {"sway_damping_linear", &VehicleModel::sway_damping_linear, "N s/m", kNonNegative,
     "feed-forward F(v), linear term"},
    {"sway_damping_quadratic", &VehicleModel::sway_damping_quadratic, "N s^2/m^2", kNonNegative,
     "feed-forward F(v), quadratic term"},
    {"pilot_gain",
     &VehicleModel::pilot_gain,
     "",
     {0, 0.5, true, false},
     "ArduSub's pilot gain on the x, y sticks"},
    {"deadband_low_us",
     &VehicleModel::deadband_low_us,
     "us",
     {1100, 1500, true, false},
     "T200 ESC dead band, low end"},
    {"deadband_high_us",
     &VehicleModel::deadband_high_us,
     "us",
     {1500, 1900, false, true},
     "T200 ESC dead band, high end"},
    {"max_forward_n", &VehicleModel::max_forward_n, "N", kPositive, "T200 thrust at 1900 us"},
    {"max_reverse_n", &VehicleModel::max_reverse_n, "N", kPositive, "T200 thrust at 1100 us"},
    {"thrust_exponent", &VehicleModel::thrust_exponent, "", kPositive,
     "T200 thrust ~ (PWM beyond the dead band)^exponent"},
    {"full_stick_yaw_rate_radps", &VehicleModel::full_stick_yaw_rate_radps, "rad/s", kPositive,
     "yaw rate a full r stick asks for"},
    {"full_stick_climb_rate_mps", &VehicleModel::full_stick_climb_rate_mps, "m/s", kPositive,
     "climb rate a full z stick asks for"},
};

const Param<SafetyConfig> kSafetyParams[] = {
    {"startup_s", &SafetyConfig::startup_s, "s", kNonNegative,
     "armed, in depth hold, held still before the first leg"},
    {"pose_timeout_s", &SafetyConfig::pose_timeout_s, "s", kPositive,
     "no valid relative pose for this long: hold"},
    {"backoff_after_s", &SafetyConfig::backoff_after_s, "s", kPositive,
     "no valid pose for this long: back away (at least pose_timeout_s)"},
    {"backoff_speed_mps", &SafetyConfig::backoff_speed_mps, "m/s", kPositive,
     "backing away, slowly so a net that reappears is not lost again"},
    {"backoff_max_m", &SafetyConfig::backoff_max_m, "m", kPositive, "then hold again"},
    {"dvl_timeout_s", &SafetyConfig::dvl_timeout_s, "s", kPositive,
     "no DVL sample for this long: the open-loop strategy"},
    {"dvl_gate_mps", &SafetyConfig::dvl_gate_mps, "m/s", kPositive,
     "a DVL sample this far from the observer's velocity is a spike, unless the next agrees"},
};

// The net must stay in view: a heading of 1 rad from the net's normal is at the edge of it.
const Param<Leg> kLegParams[] = {
    {.key = "d_ref_m",
     .member = &Leg::d_ref_m,
     .unit = "m",
     .range = kPositive,
     .help = "distance to hold from the net",
     .required = true},
    {"heading_ref_rad",
     &Leg::heading_ref_rad,
     "rad",
     {-1, 1, true, true},
     "net-relative heading (0: squarely, > 0: turned right, as psi_net)"},
    {"sway_speed_mps", &Leg::sway_speed_mps, "m/s", kAnyNumber,
     "along the net (> 0: to the right), at most limits.sway_speed_mps"},
    {"depth_m", &Leg::depth_m, "m", kNonNegative,
     "depth of the leg (absent: the depth at its start)"},
    {"duration_s", &Leg::duration_s, "s", kPositiveOrInfinite,
     "the leg ends after this (absent: never)"},
    {"length_m", &Leg::length_m, "m", kPositiveOrInfinite,
     "the leg ends once this is travelled along the net (absent: never)"},
};

// The PID loops, each a YAML section under gains: with kGainParams.
struct GainLoop {
  const char* key;
  PidGains LoopGains::*gains;
};
constexpr GainLoop kGainLoops[] = {
    {"surge_position", &LoopGains::surge_position},
    {"surge_velocity", &LoopGains::surge_velocity},
    {"sway_position", &LoopGains::sway_position},
    {"yaw", &LoopGains::yaw},
};

template <class Config>
void read_section(const YamlMap& parent, const std::string& key,
                  std::span<const Param<Config>> params, Config& config) {
  if (const auto m = parent.optional_map(key)) {
    read_params(*m, params, config);
    m->check_unknown_keys();
  }
}

// `where` is "FILE: key 'PREFIX", so messages read like the YAML reader's own.
void require(bool ok, const std::string& where, const std::string& key, const std::string& what) {
  if (!ok) throw Error(where + key + "': " + what);
}

}  // namespace

std::string control_param_rows() {
  const ControlConfig d;
  std::string rows;
  for (const GainLoop& loop : kGainLoops) {
    rows += param_table_rows<PidGains>(kGainParams, d.gains.*loop.gains,
                                       "gains." + std::string(loop.key) + ".");
  }
  rows += param_table_rows<LoopLimits>(kLimitParams, d.limits, "limits.");
  rows += param_table_rows<VehicleModel>(kVehicleParams, d.vehicle, "vehicle.");
  rows += param_table_rows<SafetyConfig>(kSafetyParams, d.safety, "safety.");
  rows += param_table_rows<Leg>(kLegParams, Leg{}, "legs[].");
  return rows;
}

void validate(const ControlConfig& c, const std::string& file, const std::string& key_prefix) {
  const std::string where = file + ": key '" + key_prefix;
  for (const GainLoop& loop : kGainLoops) {
    check_params<PidGains>(c.gains.*loop.gains, kGainParams, file,
                           key_prefix + "gains." + loop.key + ".");
  }
  require(c.gains.surge_position.kp > 0, where, "gains.surge_position.kp",
          "0 leaves the distance to the net uncontrolled; the published value is 3.0");
  require(c.gains.yaw.kp > 0, where, "gains.yaw.kp",
          "0 leaves the heading uncontrolled; the published value is 0.075");
  check_params<LoopLimits>(c.limits, kLimitParams, file, key_prefix + "limits.");
  const auto& v = c.vehicle;
  check_params<VehicleModel>(v, kVehicleParams, file, key_prefix + "vehicle.");
  require(v.surge_damping_linear + v.surge_damping_quadratic > 0 &&
              v.sway_damping_linear + v.sway_damping_quadratic > 0,
          where, "vehicle", "the feed-forward needs some damping on surge and sway");
  const auto& s = c.safety;
  check_params<SafetyConfig>(s, kSafetyParams, file, key_prefix + "safety.");
  require(s.backoff_after_s >= s.pose_timeout_s, where, "safety.backoff_after_s",
          "expected a finite number >= safety.pose_timeout_s");
  require(!c.legs.empty(), where, "legs", "at least one leg is needed");
  for (size_t i = 0; i < c.legs.size(); ++i) {
    Leg leg = c.legs[i];
    const std::string k = "legs[" + std::to_string(i) + "].";
    // An absent depth (NaN) is the depth at the leg's start.
    if (std::isnan(leg.depth_m)) leg.depth_m = 0;
    check_params<Leg>(leg, kLegParams, file, key_prefix + k);
    require(std::abs(leg.sway_speed_mps) <= c.limits.sway_speed_mps, where, k + "sway_speed_mps",
            "expected |speed| <= limits.sway_speed_mps");
  }
}

ControlConfig parse_control_config(const YamlMap& map) {
  ControlConfig c;
  const std::string strategy = map.string("strategy", to_string(c.strategy));
  if (const auto s = parse_enum_name<VelocityStrategy>(kStrategyNames, strategy)) {
    c.strategy = *s;
  } else {
    map.fail("strategy", "'" + strategy + "' is not a strategy; use " +
                             enum_choices<VelocityStrategy>(kStrategyNames));
  }
  if (map.has("legs")) {
    c.legs.clear();
    for (const YamlMap& m : map.map_list("legs")) {
      Leg leg;
      read_params<Leg>(m, kLegParams, leg);
      m.check_unknown_keys();
      c.legs.push_back(leg);
    }
  }
  if (const auto g = map.optional_map("gains")) {
    for (const GainLoop& loop : kGainLoops) {
      read_section<PidGains>(*g, loop.key, kGainParams, c.gains.*loop.gains);
    }
    g->check_unknown_keys();
  }
  read_section<LoopLimits>(map, "limits", kLimitParams, c.limits);
  read_section<VehicleModel>(map, "vehicle", kVehicleParams, c.vehicle);
  read_section<SafetyConfig>(map, "safety", kSafetyParams, c.safety);
  map.check_unknown_keys();
  validate(c, map.file(), map.key_path(""));
  return c;
}

ControlConfig load_control_config(const std::string& file) {
  return parse_control_config(YamlMap::load_file(file));
}

}  // namespace pensight::control
