#include "mavlink/messages.h"

#include <algorithm>
#include <bit>
#include <string>
#include <type_traits>

#include "core/error.h"

namespace pensight::mavlink {
namespace {

// Checked against common.xml and minimal.xml of mavlink/mavlink (CRC_EXTRA recomputed from the
// field lists) and against node-mavlink's tables by tests/mavlink/node_mavlink_test.cpp.
constexpr std::array<MessageInfo, 10> kMessages = {{
    {Heartbeat::kId, 50, 9, "HEARTBEAT"},
    {SysStatus::kId, 124, 31, "SYS_STATUS"},
    {SetMode::kId, 89, 6, "SET_MODE"},
    {ScaledPressure::kId, 115, 16, "SCALED_PRESSURE"},
    {ScaledPressure2::kId, 195, 16, "SCALED_PRESSURE2"},
    {ScaledPressure3::kId, 131, 16, "SCALED_PRESSURE3"},
    {Attitude::kId, 39, 28, "ATTITUDE"},
    {ManualControl::kId, 243, 30, "MANUAL_CONTROL"},
    {RcChannelsOverride::kId, 124, 38, "RC_CHANNELS_OVERRIDE"},
    {CommandLong::kId, 152, 33, "COMMAND_LONG"},
}};

template <class T>
using Bits = std::conditional_t<sizeof(T) == 1, uint8_t,
                                std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>>;

// Moves fields between a message and its full-length payload, little-endian whatever the host's
// byte order: into the payload when packing, out of it otherwise.
class Codec {
 public:
  Codec(std::vector<uint8_t>& payload, bool packing) : payload_(payload), packing_(packing) {}
  template <class... T>
  void operator()(T&&... fields) {
    (transfer(fields), ...);
  }

 private:
  template <class T>
  void transfer(T& field) {
    if constexpr (requires { field.begin(); }) {
      for (auto& v : field) transfer(v);
    } else {
      auto bits = packing_ ? std::bit_cast<Bits<T>>(field) : Bits<T>{0};
      for (size_t i = 0; i < sizeof(T); ++i, ++at_) {
        if (packing_) {
          payload_[at_] = static_cast<uint8_t>(bits >> (8 * i));
        } else {
          bits |= static_cast<Bits<T>>(Bits<T>{payload_[at_]} << (8 * i));
        }
      }
      if (!packing_) field = std::bit_cast<T>(bits);
    }
  }

  std::vector<uint8_t>& payload_;
  const bool packing_;
  size_t at_ = 0;
};

// Each message's fields in wire order, one list for both directions (so the two cannot differ).
template <class Io>
void fields(Io& io, Heartbeat& m) {
  io(m.custom_mode, m.type, m.autopilot, m.base_mode, m.system_status, m.mavlink_version);
}
template <class Io>
void fields(Io& io, SysStatus& m) {
  io(m.onboard_control_sensors_present, m.onboard_control_sensors_enabled,
     m.onboard_control_sensors_health, m.load_permille, m.voltage_battery_mv, m.current_battery_ca,
     m.drop_rate_comm_cpercent, m.errors_comm, m.errors_count, m.battery_remaining_percent);
}
template <class Io>
void fields(Io& io, SetMode& m) {
  io(m.custom_mode, m.target_system, m.base_mode);
}
template <class Io, uint32_t Id>
void fields(Io& io, ScaledPressureOf<Id>& m) {
  io(m.time_boot_ms, m.press_abs_hpa, m.press_diff_hpa, m.temperature_cdeg,
     m.temperature_press_diff_cdeg);
}
template <class Io>
void fields(Io& io, Attitude& m) {
  io(m.time_boot_ms, m.roll_rad, m.pitch_rad, m.yaw_rad, m.rollspeed_rad_s, m.pitchspeed_rad_s,
     m.yawspeed_rad_s);
}
template <class Io>
void fields(Io& io, ManualControl& m) {
  io(m.x, m.y, m.z, m.r, m.buttons, m.target);
}
template <class Io>
void fields(Io& io, RcChannelsOverride& m) {
  // Channels 9..18 are extensions: they follow the two target bytes.
  const std::span<uint16_t, 18> channels(m.chan_raw);
  io(channels.first<8>(), m.target_system, m.target_component, channels.last<10>());
}
template <class Io>
void fields(Io& io, CommandLong& m) {
  io(m.param, m.command, m.target_system, m.target_component, m.confirmation);
}

template <class M>
const MessageInfo& info_of() {
  return *find_message(M::kId);
}

}  // namespace

const MessageInfo* find_message(uint32_t id) {
  const auto it =
      std::find_if(kMessages.begin(), kMessages.end(), [&](const auto& m) { return m.id == id; });
  return it == kMessages.end() ? nullptr : &*it;
}

template <class M>
std::vector<uint8_t> pack(const M& m) {
  std::vector<uint8_t> payload(info_of<M>().length);
  Codec codec(payload, true);
  M copy = m;  // fields() takes a mutable message, as unpacking writes through it.
  fields(codec, copy);
  return payload;
}

template <class M>
M unpack(std::span<const uint8_t> payload) {
  const MessageInfo& info = info_of<M>();
  if (payload.size() > info.length) {
    throw Error("MAVLink " + std::string(info.name) + " payload of " +
                std::to_string(payload.size()) + " bytes is longer than its " +
                std::to_string(info.length) + "; pass the payload of a frame of that message");
  }
  std::vector<uint8_t> full(payload.begin(), payload.end());
  full.resize(info.length, 0);  // the v2 truncation undone
  Codec codec(full, false);
  M m;
  fields(codec, m);
  return m;
}

template std::vector<uint8_t> pack(const Heartbeat&);
template std::vector<uint8_t> pack(const SetMode&);
template std::vector<uint8_t> pack(const SysStatus&);
template std::vector<uint8_t> pack(const ScaledPressure&);
template std::vector<uint8_t> pack(const ScaledPressure2&);
template std::vector<uint8_t> pack(const ScaledPressure3&);
template std::vector<uint8_t> pack(const Attitude&);
template std::vector<uint8_t> pack(const ManualControl&);
template std::vector<uint8_t> pack(const RcChannelsOverride&);
template std::vector<uint8_t> pack(const CommandLong&);
template Heartbeat unpack(std::span<const uint8_t>);
template SetMode unpack(std::span<const uint8_t>);
template SysStatus unpack(std::span<const uint8_t>);
template ScaledPressure unpack(std::span<const uint8_t>);
template ScaledPressure2 unpack(std::span<const uint8_t>);
template ScaledPressure3 unpack(std::span<const uint8_t>);
template Attitude unpack(std::span<const uint8_t>);
template ManualControl unpack(std::span<const uint8_t>);
template RcChannelsOverride unpack(std::span<const uint8_t>);
template CommandLong unpack(std::span<const uint8_t>);

}  // namespace pensight::mavlink
