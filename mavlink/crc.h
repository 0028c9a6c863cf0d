#pragma once
// CRC-16/MCRF4XX, which MAVLink calls X.25: polynomial 0x1021 reflected, initial value 0xFFFF, no
// final XOR. A MAVLink checksum runs over a frame's bytes after the start byte and then over the
// message's CRC_EXTRA, so two ends that disagree on a message's layout reject each other's frames.
#include <cstdint>
#include <span>

namespace pensight::mavlink {

inline constexpr uint16_t kCrcInit = 0xFFFF;

// crc extended by one byte.
uint16_t crc_accumulate(uint8_t byte, uint16_t crc);

// crc extended by every byte of `bytes`; crc16("123456789") is 0x6F91.
uint16_t crc16(std::span<const uint8_t> bytes, uint16_t crc = kCrcInit);

}  // namespace pensight::mavlink
