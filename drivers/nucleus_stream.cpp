#include "drivers/nucleus_stream.h"

#include <algorithm>
#include <cstring>

namespace pensight::drivers {
namespace {

uint16_t u16(const uint8_t* p) {
  return static_cast<uint16_t>(p[0] | (p[1] << 8));
}

uint32_t u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

double f32(const uint8_t* p) {
  const uint32_t bits = u32(p);
  float f = 0;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

constexpr size_t kStatusAt = 12, kDistanceAt = 48, kVelocityAt = 96, kTrackMinSize = 108;
constexpr int kFirstValidBit = 9;

}  // namespace

uint16_t nucleus_checksum(std::span<const uint8_t> bytes) {
  uint32_t sum = 0xB58C;
  size_t i = 0;
  for (; i + 1 < bytes.size(); i += 2) sum += u16(bytes.data() + i);
  if (i < bytes.size()) sum += static_cast<uint32_t>(bytes[i]) << 8;
  return static_cast<uint16_t>(sum);
}

std::vector<NucleusPacket> NucleusStream::feed(std::span<const uint8_t> bytes) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  std::vector<NucleusPacket> out;
  size_t at = 0;
  const auto pass_over = [&](size_t n) {
    counters_.skipped_bytes += n;
    at += n;
  };
  while (at < pending_.size()) {
    const uint8_t* p = pending_.data() + at;
    const size_t left = pending_.size() - at;
    if (p[0] != kNucleusSync) {
      const auto next = std::find(pending_.begin() + static_cast<std::ptrdiff_t>(at) + 1,
                                  pending_.end(), kNucleusSync);
      pass_over(static_cast<size_t>(next - pending_.begin()) - at);
      continue;
    }
    if (left >= 2 && p[1] != kNucleusHeaderSize) {
      pass_over(1);
      continue;
    }
    if (left < kNucleusHeaderSize) break;
    if (nucleus_checksum({p, 8}) != u16(p + 8)) {
      ++counters_.checksum_failures;
      pass_over(1);
      continue;
    }
    const size_t size = u16(p + 4);
    if (size > kNucleusMaxPayload) {
      pass_over(1);
      continue;
    }
    if (left < kNucleusHeaderSize + size) break;
    const std::span<const uint8_t> payload(p + kNucleusHeaderSize, size);
    if (nucleus_checksum(payload) != u16(p + 6)) {
      ++counters_.checksum_failures;
      pass_over(1);
      continue;
    }
    out.push_back({p[2], {payload.begin(), payload.end()}});
    ++counters_.packets;
    at += kNucleusHeaderSize + size;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
  return out;
}

std::optional<NucleusTrack> decode_nucleus_track(const NucleusPacket& packet) {
  if (packet.record_id != kNucleusBottomTrack && packet.record_id != kNucleusWaterTrack) {
    return std::nullopt;
  }
  if (packet.payload.size() < kTrackMinSize) return std::nullopt;
  const uint8_t* p = packet.payload.data();
  NucleusTrack t;
  t.bottom = packet.record_id == kNucleusBottomTrack;
  t.status = u32(p + kStatusAt);
  for (size_t i = 0; i < 3; ++i) {
    t.velocity_mps[i] = f32(p + kVelocityAt + 4 * i);
    t.velocity_valid[i] = (t.status >> (kFirstValidBit + static_cast<int>(i))) & 1u;
    t.beam_distance_m[i] = f32(p + kDistanceAt + 4 * i);
  }
  return t;
}

}  // namespace pensight::drivers
