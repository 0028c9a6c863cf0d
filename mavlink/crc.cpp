#include "mavlink/crc.h"

namespace pensight::mavlink {

// The byte-wise form of the reflected 0x1021 polynomial, as MAVLink's checksum.h computes it.
uint16_t crc_accumulate(uint8_t byte, uint16_t crc) {
  uint8_t t = byte ^ static_cast<uint8_t>(crc & 0xFF);
  t ^= static_cast<uint8_t>(t << 4);
  return static_cast<uint16_t>((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
}

uint16_t crc16(std::span<const uint8_t> bytes, uint16_t crc) {
  for (const uint8_t b : bytes) crc = crc_accumulate(b, crc);
  return crc;
}

}  // namespace pensight::mavlink
