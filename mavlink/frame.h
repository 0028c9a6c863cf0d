#pragma once
// MAVLink v2 frames: encoding, and a streaming parser that takes bytes in any chunking, never
// throws, and counts what it drops. Wire layout: STX 0xFD, payload length, incompat_flags,
// compat_flags, seq, sysid, compid, msgid (24 bits, little-endian), the payload with its trailing
// zero bytes cut off, and the CRC-16/MCRF4XX of everything after STX followed by CRC_EXTRA.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pensight::mavlink {

inline constexpr uint8_t kStxV2 = 0xFD;
inline constexpr uint8_t kStxV1 = 0xFE;
inline constexpr uint8_t kIncompatSigned = 0x01;
inline constexpr size_t kSignatureSize = 13;

struct Frame {
  uint8_t seq = 0;
  uint8_t sysid = 0;
  uint8_t compid = 0;
  uint32_t msgid = 0;
  // As the parser returns it: zero-extended to the message's full length (MessageInfo::length).
  std::vector<uint8_t> payload;
};

// f as an unsigned v2 frame, its payload's trailing zeros trimmed (one byte always kept, as the
// reference C library does). Throws pensight::Error when f.msgid is not in the message table or
// the payload is longer than the message's full length.
std::vector<uint8_t> encode_frame(const Frame& f);

// What a FrameParser met besides good frames. Every byte fed ends up in a returned or skipped
// frame, in garbage_bytes, or (until more arrives) in FrameParser::buffered().
struct ParseCounters {
  uint64_t frames = 0;         // good v2 frames returned
  uint64_t bad_crc = 0;        // candidates of a known message whose checksum failed
  uint64_t bad_length = 0;     // candidates longer than their message's full length
  uint64_t unknown_id = 0;     // v2 frames of a message not in the table, skipped unchecked
  uint64_t v1_frames = 0;      // MAVLink v1 frames (0xFE) of a known message, skipped
  uint64_t signed_frames = 0;  // signed v2 frames, skipped: pensight holds no signing key
  uint64_t garbage_bytes = 0;  // bytes outside frames, rejected candidates' start bytes included
};

class FrameParser {
 public:
  // Appends bytes to the stream and returns the good frames they complete, in order. A rejected
  // candidate costs only its start byte, so a frame hidden behind garbage or a cut-off frame is
  // still found. A v2 frame of an unknown id cannot be checked (no CRC_EXTRA) and is skipped
  // whole; v1 is not spoken here, so a v1 frame is recognised only by a good checksum (a known
  // message) and the bytes of any other count as garbage.
  std::vector<Frame> feed(std::span<const uint8_t> bytes);

  const ParseCounters& counters() const { return counters_; }
  // Bytes held for a frame not yet complete (at most one frame's worth).
  size_t buffered() const { return buffer_.size(); }

 private:
  size_t take(std::span<const uint8_t> bytes, std::vector<Frame>& frames);

  std::vector<uint8_t> buffer_;
  ParseCounters counters_;
};

}  // namespace pensight::mavlink
