#include "control/control_config.h"

#include <cmath>

#include "pipeline/dataset/strict_yaml.h"
#include "runtime/error.h"

namespace pensight::control {

const char* to_string(VelocityStrategy s) {
  return s == VelocityStrategy::kDvlFeedback ? "dvl" : "open_loop";
}

namespace {

void read_gains(const YamlMap& parent, const std::string& key, PidGains& g) {
  const auto m = parent.optional_map(key);
  if (!m) return;
  g.kp = m->number("kp", g.kp);
  g.ki = m->number("ki", g.ki);
  g.kd = m->number("kd", g.kd);
  m->check_unknown_keys();
}

Leg read_leg(const YamlMap& m) {
  Leg leg;
  leg.d_ref_m = m.number("d_ref_m");
  leg.heading_ref_rad = m.number("heading_ref_rad", leg.heading_ref_rad);
  leg.sway_speed_mps = m.number("sway_speed_mps", leg.sway_speed_mps);
  leg.depth_m = m.number("depth_m", leg.depth_m);
  leg.duration_s = m.number("duration_s", leg.duration_s);
  leg.length_m = m.number("length_m", leg.length_m);
  m.check_unknown_keys();
  return leg;
}

// `where` is "FILE: key 'PREFIX", so messages read like the YAML reader's own.
void require(bool ok, const std::string& where, const std::string& key, const std::string& what) {
  if (!ok) throw Error(where + key + "': " + what);
}

void check_gains(const PidGains& g, const std::string& where, const std::string& key) {
  for (const auto& [name, v] : {std::pair{"kp", g.kp}, {"ki", g.ki}, {"kd", g.kd}}) {
    require(std::isfinite(v) && v >= 0, where, key + "." + name,
            "a gain is a finite number >= 0 (the loop's sign is fixed by the controller)");
  }
}

void check_positive(double v, const std::string& where, const std::string& key) {
  require(std::isfinite(v) && v > 0, where, key, "expected a finite number > 0");
}

}  // namespace

void validate(const ControlConfig& c, const std::string& file, const std::string& key_prefix) {
  const std::string where = file + ": key '" + key_prefix;
  check_gains(c.gains.surge_position, where, "gains.surge_position");
  check_gains(c.gains.surge_velocity, where, "gains.surge_velocity");
  check_gains(c.gains.sway_position, where, "gains.sway_position");
  check_gains(c.gains.yaw, where, "gains.yaw");
  require(c.gains.surge_position.kp > 0, where, "gains.surge_position.kp",
          "0 leaves the distance to the net uncontrolled; the published value is 3.0");
  require(c.gains.yaw.kp > 0, where, "gains.yaw.kp",
          "0 leaves the heading uncontrolled; the published value is 0.075");
  const auto& l = c.limits;
  check_positive(l.surge_speed_mps, where, "limits.surge_speed_mps");
  check_positive(l.sway_speed_mps, where, "limits.sway_speed_mps");
  check_positive(l.yaw_rate_radps, where, "limits.yaw_rate_radps");
  check_positive(l.climb_rate_mps, where, "limits.climb_rate_mps");
  check_positive(l.depth_gain_per_s, where, "limits.depth_gain_per_s");
  check_positive(l.force_rate_n_per_s, where, "limits.force_rate_n_per_s");
  const auto& v = c.vehicle;
  for (const auto& [name, x] : {std::pair{"surge_damping_linear", v.surge_damping_linear},
                                {"surge_damping_quadratic", v.surge_damping_quadratic},
                                {"sway_damping_linear", v.sway_damping_linear},
                                {"sway_damping_quadratic", v.sway_damping_quadratic}}) {
    require(std::isfinite(x) && x >= 0, where, std::string("vehicle.") + name,
            "expected a finite number >= 0");
  }
  require(v.surge_damping_linear + v.surge_damping_quadratic > 0 &&
              v.sway_damping_linear + v.sway_damping_quadratic > 0,
          where, "vehicle", "the feed-forward needs some damping on surge and sway");
  require(std::isfinite(v.pilot_gain) && v.pilot_gain > 0 && v.pilot_gain <= 0.5, where,
          "vehicle.pilot_gain",
          "expected a number in (0, 0.5]: above it ArduSub rescales a combined surge and sway "
          "stick, which the controller's stick model (stick_map.h) does not");
  require(std::isfinite(v.deadband_low_us) && std::isfinite(v.deadband_high_us) &&
              1100 < v.deadband_low_us && v.deadband_low_us <= 1500 && 1500 <= v.deadband_high_us &&
              v.deadband_high_us < 1900,
          where, "vehicle.deadband_low_us", "expected 1100 < low <= 1500 <= high < 1900 (us)");
  check_positive(v.max_forward_n, where, "vehicle.max_forward_n");
  check_positive(v.max_reverse_n, where, "vehicle.max_reverse_n");
  check_positive(v.thrust_exponent, where, "vehicle.thrust_exponent");
  check_positive(v.full_stick_yaw_rate_radps, where, "vehicle.full_stick_yaw_rate_radps");
  check_positive(v.full_stick_climb_rate_mps, where, "vehicle.full_stick_climb_rate_mps");
  const auto& s = c.safety;
  check_positive(s.startup_s + 1, where, "safety.startup_s");
  check_positive(s.pose_timeout_s, where, "safety.pose_timeout_s");
  require(std::isfinite(s.backoff_after_s) && s.backoff_after_s >= s.pose_timeout_s, where,
          "safety.backoff_after_s", "expected a finite number >= safety.pose_timeout_s");
  check_positive(s.backoff_speed_mps, where, "safety.backoff_speed_mps");
  check_positive(s.backoff_max_m, where, "safety.backoff_max_m");
  check_positive(s.dvl_timeout_s, where, "safety.dvl_timeout_s");
  check_positive(s.dvl_gate_mps, where, "safety.dvl_gate_mps");
  require(!c.legs.empty(), where, "legs", "at least one leg is needed");
  for (size_t i = 0; i < c.legs.size(); ++i) {
    const Leg& leg = c.legs[i];
    const std::string k = "legs[" + std::to_string(i) + "]";
    check_positive(leg.d_ref_m, where, k + ".d_ref_m");
    require(std::isfinite(leg.heading_ref_rad) && std::abs(leg.heading_ref_rad) < 1.0, where,
            k + ".heading_ref_rad", "expected |heading| < 1 rad (the net must stay in view)");
    require(std::isfinite(leg.sway_speed_mps) && std::abs(leg.sway_speed_mps) <= l.sway_speed_mps,
            where, k + ".sway_speed_mps", "expected |speed| <= limits.sway_speed_mps");
    require(std::isnan(leg.depth_m) || (std::isfinite(leg.depth_m) && leg.depth_m >= 0), where,
            k + ".depth_m", "expected a depth >= 0 m");
    require(leg.duration_s > 0 && !std::isnan(leg.duration_s), where, k + ".duration_s",
            "expected a number > 0 (leave it out for a leg without end)");
    require(leg.length_m > 0 && !std::isnan(leg.length_m), where, k + ".length_m",
            "expected a number > 0 (leave it out for a leg without end)");
  }
}

ControlConfig parse_control_config(const YamlMap& map) {
  ControlConfig c;
  const std::string strategy = map.string("strategy", to_string(c.strategy));
  if (strategy == "dvl") {
    c.strategy = VelocityStrategy::kDvlFeedback;
  } else if (strategy == "open_loop") {
    c.strategy = VelocityStrategy::kOpenLoop;
  } else {
    map.fail("strategy", "'" + strategy + "' is not a strategy; use dvl or open_loop");
  }
  if (map.has("legs")) {
    c.legs.clear();
    for (const YamlMap& m : map.map_list("legs")) c.legs.push_back(read_leg(m));
  }
  if (const auto g = map.optional_map("gains")) {
    read_gains(*g, "surge_position", c.gains.surge_position);
    read_gains(*g, "surge_velocity", c.gains.surge_velocity);
    read_gains(*g, "sway_position", c.gains.sway_position);
    read_gains(*g, "yaw", c.gains.yaw);
    g->check_unknown_keys();
  }
  if (const auto m = map.optional_map("limits")) {
    auto& l = c.limits;
    l.surge_speed_mps = m->number("surge_speed_mps", l.surge_speed_mps);
    l.sway_speed_mps = m->number("sway_speed_mps", l.sway_speed_mps);
    l.yaw_rate_radps = m->number("yaw_rate_radps", l.yaw_rate_radps);
    l.climb_rate_mps = m->number("climb_rate_mps", l.climb_rate_mps);
    l.depth_gain_per_s = m->number("depth_gain_per_s", l.depth_gain_per_s);
    l.force_rate_n_per_s = m->number("force_rate_n_per_s", l.force_rate_n_per_s);
    m->check_unknown_keys();
  }
  if (const auto m = map.optional_map("vehicle")) {
    auto& v = c.vehicle;
    v.surge_damping_linear = m->number("surge_damping_linear", v.surge_damping_linear);
    v.surge_damping_quadratic = m->number("surge_damping_quadratic", v.surge_damping_quadratic);
    v.sway_damping_linear = m->number("sway_damping_linear", v.sway_damping_linear);
    v.sway_damping_quadratic = m->number("sway_damping_quadratic", v.sway_damping_quadratic);
    v.surge_mass_kg = m->number("surge_mass_kg", v.surge_mass_kg);
    v.sway_mass_kg = m->number("sway_mass_kg", v.sway_mass_kg);
    v.pilot_gain = m->number("pilot_gain", v.pilot_gain);
    v.deadband_low_us = m->number("deadband_low_us", v.deadband_low_us);
    v.deadband_high_us = m->number("deadband_high_us", v.deadband_high_us);
    v.max_forward_n = m->number("max_forward_n", v.max_forward_n);
    v.max_reverse_n = m->number("max_reverse_n", v.max_reverse_n);
    v.thrust_exponent = m->number("thrust_exponent", v.thrust_exponent);
    v.full_stick_yaw_rate_radps =
        m->number("full_stick_yaw_rate_radps", v.full_stick_yaw_rate_radps);
    v.full_stick_climb_rate_mps =
        m->number("full_stick_climb_rate_mps", v.full_stick_climb_rate_mps);
    m->check_unknown_keys();
  }
  if (const auto m = map.optional_map("safety")) {
    auto& s = c.safety;
    s.startup_s = m->number("startup_s", s.startup_s);
    s.pose_timeout_s = m->number("pose_timeout_s", s.pose_timeout_s);
    s.backoff_after_s = m->number("backoff_after_s", s.backoff_after_s);
    s.backoff_speed_mps = m->number("backoff_speed_mps", s.backoff_speed_mps);
    s.backoff_max_m = m->number("backoff_max_m", s.backoff_max_m);
    s.dvl_timeout_s = m->number("dvl_timeout_s", s.dvl_timeout_s);
    s.dvl_gate_mps = m->number("dvl_gate_mps", s.dvl_gate_mps);
    m->check_unknown_keys();
  }
  map.check_unknown_keys();
  validate(c, map.file(), map.key_path(""));
  return c;
}

ControlConfig load_control_config(const std::string& file) {
  return parse_control_config(YamlMap::load_file(file));
}

}  // namespace pensight::control
