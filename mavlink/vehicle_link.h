#pragma once
// The MAVLink link to an ArduSub vehicle as a vehicle program or the closed loop uses it. It has
// no thread and no clock of its own: the caller passes its time (int64 ns, one clock throughout)
// to poll(), which reads what arrived and sends HEARTBEAT at 1 Hz and the manual control at
// 10 Hz. A watchdog sends the neutral command (x = y = r = 0, z = 500) whenever the latest
// command is older than the timeout, so a stalled caller leaves the vehicle holding still.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset_types.h"
#include "core/device_clock.h"
#include "mavlink/endpoint.h"
#include "mavlink/frame.h"
#include "mavlink/messages.h"
#include "mavlink/vehicle_status.h"
#include "mavlink/water_depth.h"

namespace pensight::mavlink {

// ArduSub's mode numbers (ArduSub/mode.h), sent as SET_MODE's custom_mode.
enum class SubMode : uint32_t {
  kStabilize = 0,
  kAltHold = 2,
  kGuided = 4,
  kPosHold = 16,
  kManual = 19,
};

enum class LinkRole {
  kGroundStation,      // sysid 255, MAV_COMP_ID_MISSIONPLANNER, MAV_TYPE_GCS
  kCompanionComputer,  // sysid 1, MAV_COMP_ID_ONBOARD_COMPUTER, MAV_TYPE_ONBOARD_CONTROLLER
};

struct LinkConfig {
  std::string endpoint = "udpin:0.0.0.0:14550";  // endpoint.h
  LinkRole role = LinkRole::kGroundStation;
  uint8_t sysid = 0;   // 0: the role's
  uint8_t compid = 0;  // 0: the role's
  uint8_t target_system = 1;
  uint8_t target_component = kCompIdAutopilot;
  int64_t heartbeat_period_ns = 1'000'000'000;
  int64_t control_period_ns = 100'000'000;
  int64_t command_timeout_ns = 500'000'000;
  // RC_CHANNELS_OVERRIDE with ArduSub's channels (5 forward, 6 lateral, 3 throttle, 4 yaw; 1500
  // us neutral, +-400 us full scale) instead of MANUAL_CONTROL.
  bool rc_override = false;
  WaterDepthParams water_depth;  // which barometer reads the water, and the water's density
  DeviceClockParams boot_clock;  // the vehicle's time_boot_ms onto poll()'s clock
};

struct LinkCounters {
  uint64_t frames_sent = 0;
  uint64_t send_errors = 0;       // Connection::errors()
  uint64_t neutral_commands = 0;  // sent by the watchdog
  uint64_t other_senders = 0;     // good frames not from the target vehicle, ignored
  uint64_t samples_dropped = 0;   // attitude or depth samples not taken in time
  ParseCounters parse;            // parse.frames: frames received
};

class VehicleLink {
 public:
  // Opens the endpoint. Throws pensight::Error (endpoint.h) for a bad endpoint or a socket that
  // cannot be opened, and naming the key for water_depth or boot_clock out of range; nothing
  // after construction throws for what happens on the network.
  explicit VehicleLink(LinkConfig config);

  // Reads every frame that arrived, then sends what is due at now_ns (non-decreasing).
  void poll(int64_t now_ns);

  // The command poll() sends from now on, stamped on poll()'s clock: fresh while it is within the
  // timeout of now_ns (either side, so a stamp from another clock is stale). Values are clamped:
  // x, y, r to -1000..1000, z to 0..1000.
  void set_manual_control(int x, int y, int z, int r, int64_t stamped_ns, uint16_t buttons = 0);

  // COMMAND_LONG MAV_CMD_COMPONENT_ARM_DISARM and SET_MODE, sent at once; false when not sent.
  bool arm(bool armed);
  bool set_mode(SubMode mode);
  // COMMAND_LONG MAV_CMD_SET_MESSAGE_INTERVAL: the vehicle sends `msgid` at rate_hz on this link
  // (ArduSub honours it per link); false when not sent.
  bool request_message_rate(uint32_t msgid, double rate_hz);

  // The attitude (ATTITUDE) and depth (the water's barometer, water_depth.h) samples decoded since
  // the last call, in arrival order, each stamped on poll()'s clock at its own time_boot_ms
  // through a DeviceClock per message (the link's jitter removed; device_ns the raw time_boot_ms).
  // At most kMaxQueuedSamples of each wait between calls; older ones are dropped and counted.
  std::vector<AttitudeSample> take_attitude_samples();
  std::vector<PressureSample> take_pressure_samples();
  static constexpr size_t kMaxQueuedSamples = 1000;

  const VehicleStatus& status() const { return status_; }
  LinkCounters counters() const;
  uint16_t local_port() const { return socket_.local_port(); }

 private:
  struct Command {
    int16_t x = 0, y = 0, z = 500, r = 0;
    uint16_t buttons = 0;
    int64_t stamped_ns = 0;
  };

  template <class M>
  bool send(const M& message);
  void send_command(int64_t now_ns);
  void handle(const Frame& frame, int64_t now_ns);
  template <class Sample>
  void queue(std::vector<Sample>& samples, const Sample& s);

  const LinkConfig config_;
  uint8_t sysid_, compid_, type_;
  Connection socket_;
  FrameParser parser_;
  std::vector<uint8_t> received_;
  uint8_t seq_ = 0;
  std::optional<int64_t> next_heartbeat_ns_, next_command_ns_;
  std::optional<Command> command_;
  VehicleStatus status_;
  LinkCounters counters_;
  DeviceClock attitude_clock_, pressure_clock_;
  std::vector<AttitudeSample> attitudes_;
  std::vector<PressureSample> pressures_;
};

}  // namespace pensight::mavlink
