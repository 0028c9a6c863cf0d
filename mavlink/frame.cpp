#include "mavlink/frame.h"

#include <string>

#include "core/error.h"
#include "mavlink/crc.h"
#include "mavlink/messages.h"

namespace pensight::mavlink {
namespace {

constexpr size_t kHeaderV2 = 10;
constexpr size_t kHeaderV1 = 6;
constexpr size_t kChecksumSize = 2;

// The checksum of a frame whose header and payload are `covered` (start byte included), as the
// frame's last two bytes carry it.
uint16_t frame_crc(std::span<const uint8_t> covered, uint8_t crc_extra) {
  return crc_accumulate(crc_extra, crc16(covered.subspan(1)));
}

}  // namespace

std::vector<uint8_t> encode_frame(const Frame& f) {
  const MessageInfo* info = find_message(f.msgid);
  if (info == nullptr) {
    throw Error("MAVLink message id " + std::to_string(f.msgid) +
                " is not in pensight's table; add it to mavlink/messages.cpp with its CRC_EXTRA "
                "and length from common.xml");
  }
  if (f.payload.size() > info->length) {
    throw Error("MAVLink " + std::string(info->name) + " payload of " +
                std::to_string(f.payload.size()) + " bytes is longer than its " +
                std::to_string(info->length) + "; build it with pack()");
  }
  size_t length = f.payload.size();
  while (length > 1 && f.payload[length - 1] == 0) --length;
  const auto byte = [](uint64_t v) { return static_cast<uint8_t>(v); };
  std::vector<uint8_t> out = {kStxV2, byte(length), 0, 0, f.seq, f.sysid, f.compid};
  for (const int shift : {0, 8, 16}) out.push_back(byte(f.msgid >> shift));
  out.insert(out.end(), f.payload.begin(), f.payload.begin() + static_cast<ptrdiff_t>(length));
  const uint16_t crc = frame_crc(out, info->crc_extra);
  out.push_back(byte(crc));
  out.push_back(byte(crc >> 8));
  return out;
}

std::vector<Frame> FrameParser::feed(std::span<const uint8_t> bytes) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::vector<Frame> frames;
  size_t at = 0;
  while (at < buffer_.size()) {
    const size_t used = take(std::span(buffer_).subspan(at), frames);
    if (used == 0) break;
    at += used;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<ptrdiff_t>(at));
  return frames;
}

// Handles the front of `b`: returns the bytes it used up (a frame, or one byte of garbage), or 0
// when the candidate frame there needs more bytes first.
size_t FrameParser::take(std::span<const uint8_t> b, std::vector<Frame>& frames) {
  const auto skip_byte = [&] {
    ++counters_.garbage_bytes;
    return size_t{1};
  };
  const auto reject = [&](uint64_t& reason) {
    ++reason;
    return skip_byte();
  };
  const bool v2 = b[0] == kStxV2;
  if (!v2 && b[0] != kStxV1) return skip_byte();
  const size_t header = v2 ? kHeaderV2 : kHeaderV1;
  if (b.size() < header) return 0;
  const uint8_t length = b[1];
  const uint8_t incompat = v2 ? b[2] : 0;
  // An incompatibility flag pensight does not know may change the layout: not a frame it can read.
  if ((incompat & ~kIncompatSigned) != 0) return skip_byte();
  const uint32_t msgid = v2 ? b[7] | (b[8] << 8) | (b[9] << 16) : b[5];
  const MessageInfo* info = find_message(msgid);
  if (info != nullptr && length > info->length) return reject(counters_.bad_length);
  const bool is_signed = (incompat & kIncompatSigned) != 0;
  const size_t size = header + length + kChecksumSize + (is_signed ? kSignatureSize : 0);
  if (b.size() < size) return 0;
  if (info == nullptr) {
    if (!v2) return skip_byte();
    ++counters_.unknown_id;
    return size;
  }
  const uint16_t crc = frame_crc(b.first(header + length), info->crc_extra);
  if (b[header + length] != (crc & 0xFF) || b[header + length + 1] != (crc >> 8)) {
    return reject(counters_.bad_crc);
  }
  if (!v2 || is_signed) {
    ++(v2 ? counters_.signed_frames : counters_.v1_frames);
    return size;
  }
  Frame& f = frames.emplace_back();
  f.seq = b[4];
  f.sysid = b[5];
  f.compid = b[6];
  f.msgid = msgid;
  f.payload.assign(b.begin() + header, b.begin() + static_cast<ptrdiff_t>(header + length));
  f.payload.resize(info->length, 0);
  ++counters_.frames;
  return size;
}

}  // namespace pensight::mavlink
