#pragma once
// The Nortek Nucleus 1000's binary stream (its TCP data port 9002, or its serial line): packets of
// a 10-byte little-endian header (sync 0xA5, header size 10, record id, family 0x20, data size,
// data checksum, header checksum over the first 8 bytes) and a payload, with ASCII command replies
// between them. Checksum: 0xB58C plus each little-endian 16-bit word, an odd last byte added as its
// value << 8, modulo 2^16. Records decoded here: bottom track 0xB4, water track 0xBE, altimeter
// 0xAA, AHRS 0xD2 (field offsets as Nortek's own nucleus_driver parser reads them).
//
// Bytes may arrive in any chunking; what is not a packet with both checksums good is passed over
// and counted, never an exception. Cost: O(bytes) and one copy of each payload. The writer
// (encode_nucleus_packet) serves the device stand-ins.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pensight::drivers {

inline constexpr uint8_t kNucleusSync = 0xA5, kNucleusHeaderSize = 10, kNucleusFamily = 0x20;
inline constexpr uint8_t kNucleusBottomTrack = 0xB4, kNucleusWaterTrack = 0xBE,
                         kNucleusAltimeter = 0xAA, kNucleusAhrs = 0xD2;
// A larger data size is a corrupt header: the largest record Nortek documents is well below.
inline constexpr size_t kNucleusMaxPayload = 4096;

uint16_t nucleus_checksum(std::span<const uint8_t> bytes);

struct NucleusPacket {
  uint8_t record_id = 0;
  std::vector<uint8_t> payload;
};

struct NucleusStreamCounters {
  size_t packets = 0;            // returned, both checksums good
  size_t checksum_failures = 0;  // header or data checksum wrong: its sync byte passed over
  size_t skipped_bytes = 0;      // outside packets (ASCII replies, noise, corrupt headers)
};

class NucleusStream {
 public:
  // The complete packets these bytes finish, in stream order; an incomplete one is kept for the
  // next call.
  std::vector<NucleusPacket> feed(std::span<const uint8_t> bytes);
  // A new connection: the last one's unfinished packet is forgotten, the counters kept.
  void restart() { pending_.clear(); }
  const NucleusStreamCounters& counters() const { return counters_; }

 private:
  std::vector<uint8_t> pending_;
  NucleusStreamCounters counters_;
};

// Every record's common part: version (byte 0), the offset of its data block (byte 1), a status
// byte (byte 2, bit 0: the time is POSIX), the device's clock in seconds (u32 at 4) and
// microseconds (u32 at 8). nullopt for a payload shorter than these 12 bytes.
struct NucleusTime {
  int64_t device_ns = 0;  // seconds * 1e9 + microseconds * 1e3
  bool posix = false;     // the clock counts from 1970-01-01 UTC (set by SETCLOCKSTR)
};
std::optional<NucleusTime> nucleus_time(const NucleusPacket& packet);

// Bottom track (0xB4) or water track (0xBE): velocities in the DVL's XYZ frame at payload bytes
// 96-107 (float32), their valid flags bits 9-11 of the status word at byte 12, the three beams'
// distances at bytes 48-59 (float32, metres). An invalid velocity reads -32.768 m/s.
struct NucleusTrack {
  NucleusTime time;
  bool bottom = true;  // false: water track
  uint32_t status = 0;
  std::array<double, 3> velocity_mps{};
  std::array<bool, 3> velocity_valid{};
  std::array<double, 3> beam_distance_m{};
  bool valid() const { return velocity_valid[0] && velocity_valid[1] && velocity_valid[2]; }
};

// nullopt for another record or a payload too short for the fields.
std::optional<NucleusTrack> decode_nucleus_track(const NucleusPacket& packet);

// The packet's bytes on the wire: its header (both checksums) and payload. A payload over
// kNucleusMaxPayload is the caller's error (pensight::Error).
std::vector<uint8_t> encode_nucleus_packet(const NucleusPacket& packet);
// A bottom- or water-track record of the fields decode_nucleus_track reads (the rest zero, 108
// bytes): the device stand-in's (live/device_standins.h). An invalid velocity is written as
// -32.768 m/s, the status's valid bits from velocity_valid.
NucleusPacket nucleus_track_packet(const NucleusTrack& track);

// AHRS (0xD2): from the data block (offset at byte 1) roll, pitch, heading (float32, degrees),
// the orientation quaternion w, x, y, z (float32), then a 3x3 rotation matrix, the declination
// and the depth (float32 at +68, metres).
struct NucleusAhrs {
  NucleusTime time;
  double roll_deg = 0, pitch_deg = 0, heading_deg = 0;
  std::array<double, 4> quaternion_wxyz{};
  double depth_m = 0;
};
// nullopt for another record or a payload too short for the fields.
std::optional<NucleusAhrs> decode_nucleus_ahrs(const NucleusPacket& packet);

// Altimeter (0xAA): status word at byte 12 (bit 0: the distance is valid, bit 1: its quality),
// temperature (float32 at 28, deg C), pressure (float32 at 32, dbar), distance (float32 at 36,
// metres), quality (u16 at 40).
struct NucleusAltimeter {
  NucleusTime time;
  uint32_t status = 0;
  double temperature_c = 0, pressure_dbar = 0, distance_m = 0;
  uint16_t quality = 0;
  bool valid() const { return status & 1u; }
};
// nullopt for another record or a payload too short for the fields.
std::optional<NucleusAltimeter> decode_nucleus_altimeter(const NucleusPacket& packet);

}  // namespace pensight::drivers
