#pragma once
// The Nortek Nucleus 1000's binary stream (its TCP data port 9002, or its serial line): packets of
// a 10-byte little-endian header (sync 0xA5, header size 10, record id, family 0x20, data size,
// data checksum, header checksum over the first 8 bytes) and a payload, with ASCII command replies
// between them. Checksum: 0xB58C plus each little-endian 16-bit word, an odd last byte added as its
// value << 8, modulo 2^16. Records: bottom track 0xB4 and water track 0xBE (decoded here),
// altimeter 0xAA, AHRS 0xD2.
//
// Bytes may arrive in any chunking; what is not a packet with both checksums good is passed over
// and counted, never an exception. Cost: O(bytes) and one copy of each payload.
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
  const NucleusStreamCounters& counters() const { return counters_; }

 private:
  std::vector<uint8_t> pending_;
  NucleusStreamCounters counters_;
};

// Bottom track (0xB4) or water track (0xBE): velocities in the DVL's XYZ frame at payload bytes
// 96-107 (float32), their valid flags bits 9-11 of the status word at byte 12, the three beams'
// distances at bytes 48-59 (float32, metres). An invalid velocity reads -32.768 m/s.
struct NucleusTrack {
  bool bottom = true;  // false: water track
  uint32_t status = 0;
  std::array<double, 3> velocity_mps{};
  std::array<bool, 3> velocity_valid{};
  std::array<double, 3> beam_distance_m{};
  bool valid() const { return velocity_valid[0] && velocity_valid[1] && velocity_valid[2]; }
};

// nullopt for another record or a payload too short for the fields.
std::optional<NucleusTrack> decode_nucleus_track(const NucleusPacket& packet);

}  // namespace pensight::drivers
