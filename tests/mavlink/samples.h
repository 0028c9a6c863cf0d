#pragma once
// Random MAVLink messages of every type pensight knows and their fields under common.xml's names,
// for round trips and for the comparison with node-mavlink.
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <type_traits>
#include <utility>

#include "mavlink/messages.h"
#include "tests/support/test_seed.h"

namespace pensight::mavlink::testing {

using Fields = std::map<std::string, double>;

// Calls v(name, field) for each name and field of the list.
template <class V, class T, class... Rest>
void each(V& v, const std::string& name, T& field, Rest&&... rest) {
  v(name, field);
  if constexpr (sizeof...(rest) > 0) each(v, std::forward<Rest>(rest)...);
}

template <class V>
void visit(Heartbeat& m, V v) {
  each(v, "custom_mode", m.custom_mode, "type", m.type, "autopilot", m.autopilot, "base_mode",
       m.base_mode, "system_status", m.system_status, "mavlink_version", m.mavlink_version);
}
template <class V>
void visit(SysStatus& m, V v) {
  each(v, "onboard_control_sensors_present", m.onboard_control_sensors_present,
       "onboard_control_sensors_enabled", m.onboard_control_sensors_enabled,
       "onboard_control_sensors_health", m.onboard_control_sensors_health, "load", m.load_permille,
       "voltage_battery", m.voltage_battery_mv, "current_battery", m.current_battery_ca,
       "drop_rate_comm", m.drop_rate_comm_cpercent, "errors_comm", m.errors_comm, "errors_count1",
       m.errors_count[0], "errors_count2", m.errors_count[1], "errors_count3", m.errors_count[2],
       "errors_count4", m.errors_count[3], "battery_remaining", m.battery_remaining_percent);
}
template <class V>
void visit(SetMode& m, V v) {
  each(v, "custom_mode", m.custom_mode, "target_system", m.target_system, "base_mode", m.base_mode);
}
template <class V, uint32_t Id>
void visit(ScaledPressureOf<Id>& m, V v) {
  each(v, "time_boot_ms", m.time_boot_ms, "press_abs", m.press_abs_hpa, "press_diff",
       m.press_diff_hpa, "temperature", m.temperature_cdeg, "temperature_press_diff",
       m.temperature_press_diff_cdeg);
}
template <class V>
void visit(Attitude& m, V v) {
  each(v, "time_boot_ms", m.time_boot_ms, "roll", m.roll_rad, "pitch", m.pitch_rad, "yaw",
       m.yaw_rad, "rollspeed", m.rollspeed_rad_s, "pitchspeed", m.pitchspeed_rad_s, "yawspeed",
       m.yawspeed_rad_s);
}
template <class V>
void visit(ManualControl& m, V v) {
  each(v, "x", m.x, "y", m.y, "z", m.z, "r", m.r, "buttons", m.buttons, "target", m.target);
}
template <class V>
void visit(RcChannelsOverride& m, V v) {
  for (size_t i = 0; i < m.chan_raw.size(); ++i)
    v("chan" + std::to_string(i + 1) + "_raw", m.chan_raw[i]);
  each(v, "target_system", m.target_system, "target_component", m.target_component);
}
template <class V>
void visit(CommandLong& m, V v) {
  for (size_t i = 0; i < m.param.size(); ++i) v("param" + std::to_string(i + 1), m.param[i]);
  each(v, "command", m.command, "target_system", m.target_system, "target_component",
       m.target_component, "confirmation", m.confirmation);
}

// Calls f(M{}) for every message type pensight knows.
template <class F>
void for_each_message_type(F f) {
  f(Heartbeat{}), f(SysStatus{}), f(SetMode{}), f(ScaledPressure{}), f(ScaledPressure2{}),
      f(ScaledPressure3{});
  f(Attitude{}), f(ManualControl{});
  f(RcChannelsOverride{}), f(CommandLong{});
}

template <class M>
Fields fields_of(M m) {
  Fields out;
  visit(m, [&](const std::string& name, auto v) { out[name] = static_cast<double>(v); });
  return out;
}

// Every field random over its whole range (any finite float), so all payload bytes get exercised.
template <class M>
M random_message(std::mt19937_64& rng) {
  M m;
  visit(m, [&](const std::string&, auto& v) {
    using T = std::remove_reference_t<decltype(v)>;
    if constexpr (std::is_same_v<T, float>) {
      uint32_t bits = 0;
      do bits = static_cast<uint32_t>(rng());
      while ((bits & 0x7F800000u) == 0x7F800000u);
      v = std::bit_cast<float>(bits);
    } else {
      v = static_cast<T>(rng());
    }
  });
  return m;
}

}  // namespace pensight::mavlink::testing
