#pragma once
// The MAVLink messages pensight exchanges with an ArduSub vehicle (common.xml), one struct each
// with the message's fields and units, and the table of their ids, CRC_EXTRA and lengths. The
// payload is the fields in wire order: sorted by type size, largest first, extensions last.
#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "mavlink/frame.h"

namespace pensight::mavlink {

// A message pensight knows. crc_extra: the hash of its base fields' types and names that ends
// every checksum of it. length: its payload with every extension field of common.xml; a frame
// may carry fewer bytes (the v2 truncation), never more.
struct MessageInfo {
  uint32_t id;
  uint8_t crc_extra;
  uint8_t length;
  std::string_view name;
};

// The table entry for id, or nullptr for a message pensight does not know.
const MessageInfo* find_message(uint32_t id);

// Values of common.xml's enums that pensight uses.
inline constexpr uint8_t kMavTypeGcs = 6;
inline constexpr uint8_t kMavTypeOnboardController = 18;
inline constexpr uint8_t kMavAutopilotInvalid = 8;
inline constexpr uint8_t kMavStateActive = 4;
inline constexpr uint8_t kModeFlagCustomModeEnabled = 0x01;
inline constexpr uint8_t kModeFlagSafetyArmed = 0x80;
inline constexpr uint16_t kCmdComponentArmDisarm = 400;
inline constexpr uint16_t kCmdSetMessageInterval = 511;
inline constexpr uint8_t kCompIdAutopilot = 1;
inline constexpr uint8_t kCompIdMissionPlanner = 190;
inline constexpr uint8_t kCompIdOnboardComputer = 191;

// HEARTBEAT: every system sends one a second. A vehicle's base_mode carries kModeFlagSafetyArmed
// when armed and custom_mode its ArduSub mode number.
struct Heartbeat {
  static constexpr uint32_t kId = 0;
  uint32_t custom_mode = 0;
  uint8_t type = 0;
  uint8_t autopilot = 0;
  uint8_t base_mode = 0;
  uint8_t system_status = 0;
  uint8_t mavlink_version = 3;
};

// SET_MODE: base_mode kModeFlagCustomModeEnabled with the ArduSub mode number in custom_mode.
// SYS_STATUS: the autopilot's sensors (bit masks), load, and the battery; extensions left out.
struct SysStatus {
  static constexpr uint32_t kId = 1;
  uint32_t onboard_control_sensors_present = 0;
  uint32_t onboard_control_sensors_enabled = 0;
  uint32_t onboard_control_sensors_health = 0;
  uint16_t load_permille = 0;
  uint16_t voltage_battery_mv = 0;  // UINT16_MAX: not sent
  int16_t current_battery_ca = 0;   // -1: not measured
  uint16_t drop_rate_comm_cpercent = 0;
  uint16_t errors_comm = 0;
  std::array<uint16_t, 4> errors_count{};
  int8_t battery_remaining_percent = 0;  // -1: not estimated
};

struct SetMode {
  static constexpr uint32_t kId = 11;
  uint32_t custom_mode = 0;
  uint8_t target_system = 0;
  uint8_t base_mode = 0;
};

// SCALED_PRESSURE (29), SCALED_PRESSURE2 (137) and SCALED_PRESSURE3 (143) share one layout, one
// barometer each; which of them reads the water (a BlueROV2's Bar30) differs by board.
template <uint32_t Id>
struct ScaledPressureOf {
  static constexpr uint32_t kId = Id;
  uint32_t time_boot_ms = 0;
  float press_abs_hpa = 0;
  float press_diff_hpa = 0;
  int16_t temperature_cdeg = 0;
  int16_t temperature_press_diff_cdeg = 0;
};
using ScaledPressure = ScaledPressureOf<29>;
using ScaledPressure2 = ScaledPressureOf<137>;
using ScaledPressure3 = ScaledPressureOf<143>;

struct Attitude {
  static constexpr uint32_t kId = 30;
  uint32_t time_boot_ms = 0;
  float roll_rad = 0;
  float pitch_rad = 0;
  float yaw_rad = 0;
  float rollspeed_rad_s = 0;
  float pitchspeed_rad_s = 0;
  float yawspeed_rad_s = 0;
};

// MANUAL_CONTROL as ArduSub reads it: x forward, y lateral, r yaw in -1000..1000, z 0..1000
// (500 holds depth). The extension fields (buttons2, aux axes) are not used, so they go out as
// zeros and are truncated.
struct ManualControl {
  static constexpr uint32_t kId = 69;
  int16_t x = 0;
  int16_t y = 0;
  int16_t z = 0;
  int16_t r = 0;
  uint16_t buttons = 0;
  uint8_t target = 0;
};

// RC_CHANNELS_OVERRIDE: pulse widths in us; chan_raw[0..7] UINT16_MAX and chan_raw[8..17] 0 leave
// a channel alone.
struct RcChannelsOverride {
  static constexpr uint32_t kId = 70;
  std::array<uint16_t, 18> chan_raw{};
  uint8_t target_system = 0;
  uint8_t target_component = 0;
};

struct CommandLong {
  static constexpr uint32_t kId = 76;
  std::array<float, 7> param{};
  uint16_t command = 0;
  uint8_t target_system = 0;
  uint8_t target_component = 0;
  uint8_t confirmation = 0;
};

// m's payload at its full length, in wire order, little-endian.
template <class M>
std::vector<uint8_t> pack(const M& m);

// The message in a payload of up to its full length, zero-extended when shorter. Throws
// pensight::Error when the payload is longer.
template <class M>
M unpack(std::span<const uint8_t> payload);

// m as a frame from (sysid, compid) with sequence number seq.
template <class M>
Frame make_frame(const M& m, uint8_t seq, uint8_t sysid, uint8_t compid) {
  return Frame{seq, sysid, compid, M::kId, pack(m)};
}

}  // namespace pensight::mavlink
