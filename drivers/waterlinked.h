#pragma once
// Water Linked DVL A50 / A125: the TCP JSON API (port 16171, one JSON object per line, `format`
// json_v3*) and the serial protocol (115200 8N1, sentences `wr<x>,<fields>*<crc>` with CRC-8,
// polynomial 0x07, init 0, over the bytes before '*', two lower-case hex digits), both as Water
// Linked's protocol documents describe them. Reports decoded: velocity (`velocity`,
// `velocity_water`; `wrz`, `wrs`, and the deprecated `wrx`), transducer (`wru`), dead reckoning
// (`position_local`, `wrp`) and command responses (`response`; `wra`, `wrn`, `wr?`, `wr!`, `wrc`,
// `wrv`, `wrw`).
//
// Lenient as a reader of another vendor's bytes: a field that older firmware does not send is
// absent (NaN, nullopt), an unknown report type or sentence is counted and passed over, and a
// line that is not a report (bad JSON, a missing required field, a bad checksum) is counted with
// its reason; nothing throws. Cost: O(bytes) per line.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "core/dataset_types.h"
#include "core/device_clock.h"
#include "core/line_stream.h"

namespace pensight::drivers {

inline constexpr int kWaterLinkedTcpPort = 16171;
inline constexpr int kWaterLinkedBeams = 4;

// CRC-8 of the serial protocol (check value: "123456789" -> 0xf4).
uint8_t waterlinked_crc8(std::string_view bytes);

// One transducer's return (JSON `transducers[i]`, serial `wru`).
struct WaterLinkedBeam {
  int id = -1;                 // 0-3: the transducer number on Water Linked's drawings minus 1
  double velocity_mps = kNaN;  // along the beam
  double distance_m = kNaN;    // along the beam to the reflecting surface; NaN: no return
  double rssi_dbm = kNaN, nsd_dbm = kNaN;
  bool valid = false;  // JSON beam_valid; serial: a distance was decoded (the wire's -1 is none)
};

// A velocity report. Axes X forward, Y right, Z down, in the DVL's body frame, or its vehicle
// frame where a mounting rotation offset is configured.
struct WaterLinkedVelocity {
  bool water_track = false;  // type velocity_water / `wrs`: velocity through the water
  std::array<double, 3> velocity_mps = {kNaN, kNaN, kNaN};
  bool valid = false;  // the DVL has a lock: velocities and altitude are valid
  double fom_mps = kNaN;
  std::array<double, 9> covariance_m2ps2 = {kNaN, kNaN, kNaN, kNaN, kNaN,
                                            kNaN, kNaN, kNaN, kNaN};  // row-major
  double altitude_m = kNaN;                                           // along Z
  std::vector<WaterLinkedBeam> beams;  // JSON only: serial sends `wru` sentences separately
  int status = 0;                      // bit 0: high temperature, thermal shutdown soon
  double since_last_report_ms = kNaN;
  std::optional<int64_t> time_of_validity_us;      // the ping's centre, the DVL's Unix clock
  std::optional<int64_t> time_of_transmission_us;  // just before it was sent
  std::string format;                              // JSON `format`, e.g. "json_v3.1"
  bool deprecated_sentence = false;                // `wrx`: no covariance, no times
};

// Dead reckoning (`position_local`, `wrp`), in the frame of the DVL at the run's start.
struct WaterLinkedDeadReckoning {
  double time_s = kNaN;
  std::array<double, 3> position_m = {kNaN, kNaN, kNaN};
  double std_m = kNaN;
  double roll_deg = kNaN, pitch_deg = kNaN, yaw_deg = kNaN;
  int status = 0;
};

// A reply to a command. JSON: `response_to` names the command, `result` is kept as JSON text.
// Serial: `response_to` is the sentence (wra ack, wrn nak, wr? malformed request, wr! checksum
// mismatch, wrc configuration, wrv protocol version, wrw product), `result` its fields.
struct WaterLinkedResponse {
  std::string response_to;
  bool success = false;
  std::string error_message;
  std::string result;
};

using WaterLinkedReport = std::variant<WaterLinkedVelocity, WaterLinkedBeam,
                                       WaterLinkedDeadReckoning, WaterLinkedResponse>;

enum class WaterLinkedLine { kReport, kUnknown, kMalformed, kBadChecksum };

struct WaterLinkedParse {
  WaterLinkedLine kind = WaterLinkedLine::kMalformed;
  std::optional<WaterLinkedReport> report;  // with kReport
  std::string error;                        // with kMalformed and kBadChecksum: why
};

// One line of the TCP JSON API, or one serial sentence (a line end after it is passed over).
WaterLinkedParse parse_waterlinked_json(std::string_view line);
WaterLinkedParse parse_waterlinked_sentence(std::string_view line);

struct WaterLinkedCounters {
  size_t reports = 0;            // returned
  size_t unknown = 0;            // well-formed, of a type not decoded here: passed over
  size_t malformed = 0;          // not a report: bad JSON, a field missing or of the wrong type
  size_t checksum_failures = 0;  // serial
  size_t superseded = 0;         // serial `wrx` after a `wrz` was seen: the same ping twice
};

// A connection's bytes, in any chunking, into reports.
class WaterLinkedStream {
 public:
  enum class Protocol { kJson, kSerial };
  explicit WaterLinkedStream(Protocol protocol) : protocol_(protocol) {}

  std::vector<WaterLinkedReport> feed(std::span<const uint8_t> bytes);
  // A new connection: the last one's unfinished line is forgotten, the counters kept.
  void restart() { lines_.discard_unfinished(); }
  const WaterLinkedCounters& counters() const { return counters_; }
  const LineStreamCounters& line_counters() const { return lines_.counters(); }
  // The reason the latest malformed or bad-checksum line was refused ("" before one).
  const std::string& last_error() const { return last_error_; }

 private:
  Protocol protocol_;
  LineStream lines_;
  WaterLinkedCounters counters_;
  std::string last_error_;
  bool seen_wrz_ = false;
};

// Commands, each a complete line to write to the connection.
struct WaterLinkedConfig {
  std::optional<double> speed_of_sound_mps;
  std::optional<double> mounting_rotation_offset_deg;
  std::optional<bool> acoustic_enabled;
  std::optional<bool> dark_mode_enabled;  // true: the LED does not flash into the camera
  std::optional<std::string> range_mode;  // "auto", "wt" (water tracking), or a range
  std::optional<bool> periodic_cycling_enabled;
};
// {"command":"<command>"}\n for get_config, calibrate_gyro, reset_dead_reckoning, trigger_ping.
std::string waterlinked_json_command(std::string_view command);
// {"command":"set_config","parameters":{...}}\n with the parameters that are set.
std::string waterlinked_json_set_config(const WaterLinkedConfig& config);
// The DVL's side of the JSON API, for stand-ins (`pensight sim-devices`) and tests:
// a velocity report (type velocity or velocity_water, format json_v3.1 unless `format` is set) as
// parse_waterlinked_json reads it back; the command a client's line names (nullopt for a line that
// is no command object); and the reply to it.
std::string waterlinked_json_velocity(const WaterLinkedVelocity& report);
std::optional<std::string> waterlinked_json_command_name(std::string_view line);
std::string waterlinked_json_response(std::string_view command, bool success);
// A serial command with its checksum and line end: "<body>*<crc>\n" (e.g. body "wcc").
std::string waterlinked_sentence(std::string_view body);
// wcs,[speed],[offset],[acoustic],[dark],[range_mode],[cycling] with the unset fields blank.
std::string waterlinked_set_config_sentence(const WaterLinkedConfig& config);

// The pipeline's DVL sample: the velocity rotated into the body by R_B_S (the rotation of
// dvl0/sensor.yaml's T_BS), valid as the report's lock, beam range r(id+1) the transducer's
// distance where its beam is valid, device_ns the time of validity (when the report has one).
DvlSample to_dvl_sample(const WaterLinkedVelocity& report, const Eigen::Matrix3d& R_B_S,
                        int64_t timestamp_ns);

// The host time of the ping a velocity report measured: its time_of_validity moved onto the host
// clock by `clock`, which learns the DVL clock's offset from time_of_transmission and the arrival
// time (the report leaves ~0.2 s after the ping, so its arrival is that late). A report without
// both times (wrx, firmware before json_v3), or whose ping is said to be after its sending or over
// 10 s before it, is stamped at its arrival.
int64_t waterlinked_ping_host_ns(const WaterLinkedVelocity& report, int64_t arrival_ns,
                                 DeviceClock& clock);

}  // namespace pensight::drivers
