#include "drivers/nucleus_stream.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "core/error.h"

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

constexpr size_t kCommonSize = 12, kSecondsAt = 4, kMicrosecondsAt = 8;
constexpr size_t kStatusAt = 12, kDistanceAt = 48, kVelocityAt = 96, kTrackMinSize = 108;
constexpr int kFirstValidBit = 9;
// AHRS: 17 float32 from the data block's offset, the depth the 18th.
constexpr size_t kAhrsFloats = 18, kAhrsDepthAt = 68;
constexpr size_t kTemperatureAt = 28, kPressureAt = 32, kAltitudeAt = 36, kQualityAt = 40,
                 kAltimeterMinSize = 42;

void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}

void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

void put_f32(uint8_t* p, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof bits);
  put_u32(p, bits);
}

constexpr double kInvalidVelocity_mps = -32.768;

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

std::optional<NucleusTime> nucleus_time(const NucleusPacket& packet) {
  if (packet.payload.size() < kCommonSize) return std::nullopt;
  const uint8_t* p = packet.payload.data();
  return NucleusTime{static_cast<int64_t>(u32(p + kSecondsAt)) * 1'000'000'000 +
                         static_cast<int64_t>(u32(p + kMicrosecondsAt)) * 1'000,
                     (p[2] & 1u) != 0};
}

std::optional<NucleusTrack> decode_nucleus_track(const NucleusPacket& packet) {
  if (packet.record_id != kNucleusBottomTrack && packet.record_id != kNucleusWaterTrack) {
    return std::nullopt;
  }
  if (packet.payload.size() < kTrackMinSize) return std::nullopt;
  const uint8_t* p = packet.payload.data();
  NucleusTrack t;
  t.time = *nucleus_time(packet);
  t.bottom = packet.record_id == kNucleusBottomTrack;
  t.status = u32(p + kStatusAt);
  for (size_t i = 0; i < 3; ++i) {
    t.velocity_mps[i] = f32(p + kVelocityAt + 4 * i);
    t.velocity_valid[i] = (t.status >> (kFirstValidBit + static_cast<int>(i))) & 1u;
    t.beam_distance_m[i] = f32(p + kDistanceAt + 4 * i);
  }
  return t;
}

std::vector<uint8_t> encode_nucleus_packet(const NucleusPacket& packet) {
  if (packet.payload.size() > kNucleusMaxPayload) {
    throw Error("Nucleus record 0x" + std::to_string(packet.record_id) + " of " +
                std::to_string(packet.payload.size()) + " bytes: larger than a record can be");
  }
  std::vector<uint8_t> out(kNucleusHeaderSize + packet.payload.size());
  out[0] = kNucleusSync;
  out[1] = kNucleusHeaderSize;
  out[2] = packet.record_id;
  out[3] = kNucleusFamily;
  put_u16(out.data() + 4, static_cast<uint16_t>(packet.payload.size()));
  put_u16(out.data() + 6, nucleus_checksum(packet.payload));
  put_u16(out.data() + 8, nucleus_checksum({out.data(), 8}));
  std::copy(packet.payload.begin(), packet.payload.end(), out.begin() + kNucleusHeaderSize);
  return out;
}

NucleusPacket nucleus_track_packet(const NucleusTrack& track) {
  NucleusPacket packet{track.bottom ? kNucleusBottomTrack : kNucleusWaterTrack,
                       std::vector<uint8_t>(kTrackMinSize, 0)};
  uint8_t* p = packet.payload.data();
  p[1] = static_cast<uint8_t>(kCommonSize);
  p[2] = track.time.posix ? 1 : 0;
  const int64_t us = track.time.device_ns / 1000;
  put_u32(p + kSecondsAt, static_cast<uint32_t>(us / 1'000'000));
  put_u32(p + kMicrosecondsAt, static_cast<uint32_t>(us % 1'000'000));
  uint32_t status = track.status;
  for (size_t i = 0; i < 3; ++i) {
    const uint32_t bit = 1u << (kFirstValidBit + static_cast<int>(i));
    status = track.velocity_valid[i] ? (status | bit) : (status & ~bit);
    put_f32(p + kVelocityAt + 4 * i,
            track.velocity_valid[i] ? track.velocity_mps[i] : kInvalidVelocity_mps);
    put_f32(p + kDistanceAt + 4 * i, track.beam_distance_m[i]);
  }
  put_u32(p + kStatusAt, status);
  return packet;
}

std::optional<NucleusAhrs> decode_nucleus_ahrs(const NucleusPacket& packet) {
  if (packet.record_id != kNucleusAhrs || packet.payload.size() < kCommonSize) return std::nullopt;
  const uint8_t* p = packet.payload.data();
  const size_t at = p[1];
  if (at < kCommonSize || packet.payload.size() < at + 4 * kAhrsFloats) return std::nullopt;
  NucleusAhrs a;
  a.time = *nucleus_time(packet);
  a.roll_deg = f32(p + at);
  a.pitch_deg = f32(p + at + 4);
  a.heading_deg = f32(p + at + 8);
  for (size_t i = 0; i < 4; ++i) a.quaternion_wxyz[i] = f32(p + at + 12 + 4 * i);
  a.depth_m = f32(p + at + kAhrsDepthAt);
  return a;
}

std::optional<NucleusAltimeter> decode_nucleus_altimeter(const NucleusPacket& packet) {
  if (packet.record_id != kNucleusAltimeter || packet.payload.size() < kAltimeterMinSize) {
    return std::nullopt;
  }
  const uint8_t* p = packet.payload.data();
  NucleusAltimeter a;
  a.time = *nucleus_time(packet);
  a.status = u32(p + kStatusAt);
  a.temperature_c = f32(p + kTemperatureAt);
  a.pressure_dbar = f32(p + kPressureAt);
  a.distance_m = f32(p + kAltitudeAt);
  a.quality = u16(p + kQualityAt);
  return a;
}

}  // namespace pensight::drivers
