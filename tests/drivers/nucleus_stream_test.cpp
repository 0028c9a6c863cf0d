// The Nucleus 1000 stream parser on Nortek's own recording (../shared/real/dvl/, a bench session:
// every velocity flagged invalid) in any chunking, and on streams spoilt the ways a serial line or
// a reconnect spoils them.
#include "drivers/nucleus_stream.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/support/nucleus_recording.h"
#include "tests/support/test_seed.h"

namespace pensight::drivers {
namespace {

using testing::nucleus_recording;

struct Parsed {
  std::map<uint8_t, size_t> by_record;
  std::vector<NucleusTrack> tracks;
  NucleusStreamCounters counters;
};

Parsed parse(const std::vector<uint8_t>& bytes, uint64_t chunk_seed) {
  NucleusStream stream;
  Parsed out;
  std::mt19937_64 rng(chunk_seed);
  std::uniform_int_distribution<size_t> chunk(1, 700);
  for (size_t at = 0; at < bytes.size();) {
    const size_t n = chunk_seed == 0 ? bytes.size() : std::min(chunk(rng), bytes.size() - at);
    for (const NucleusPacket& p : stream.feed({bytes.data() + at, n})) {
      ++out.by_record[p.record_id];
      if (const auto t = decode_nucleus_track(p)) out.tracks.push_back(*t);
    }
    at += n;
  }
  out.counters = stream.counters();
  return out;
}

TEST(NucleusStream, NortekRecordingInAnyChunking) {
  const std::vector<uint8_t> bytes = nucleus_recording();
  ASSERT_EQ(bytes.size(), 310174u);
  for (const uint64_t seed : {uint64_t{0}, uint64_t{1}, uint64_t{2}, uint64_t{3}}) {
    SCOPED_TRACE(seed);
    const Parsed p = parse(bytes, seed);
    EXPECT_EQ(p.counters.packets, 2585u);
    EXPECT_EQ(p.counters.checksum_failures, 0u);
    EXPECT_EQ(p.counters.skipped_bytes, 0u);
    EXPECT_EQ(p.by_record.at(kNucleusAhrs), 1915u);
    EXPECT_EQ(p.by_record.at(kNucleusBottomTrack), 287u);
    EXPECT_EQ(p.by_record.at(kNucleusWaterTrack), 287u);
    EXPECT_EQ(p.by_record.at(kNucleusAltimeter), 96u);
    ASSERT_EQ(p.tracks.size(), 574u);
    // A bench recording: every velocity flagged invalid and at Nortek's -32.768 m/s.
    for (const NucleusTrack& t : p.tracks) {
      EXPECT_FALSE(t.valid());
      for (const double v : t.velocity_mps) EXPECT_NEAR(v, -32.768, 1e-5);
    }
  }
}

// The writer: every packet of Nortek's recording written again from its record id and payload is
// the recording's bytes (both checksums included); a track record of random fields reads back as
// written (float32), through the stream in random chunks.
TEST(NucleusStream, WrittenPacketsAreNorteksBytesAndTracksReadBack) {
  const std::vector<uint8_t> bytes = nucleus_recording();
  NucleusStream stream;
  std::vector<uint8_t> written;
  for (const NucleusPacket& p : stream.feed(bytes)) {
    const std::vector<uint8_t> b = encode_nucleus_packet(p);
    written.insert(written.end(), b.begin(), b.end());
  }
  EXPECT_EQ(written, bytes);

  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> v(-2, 2), r(0.2, 30);
  std::vector<NucleusTrack> tracks(20);
  std::vector<uint8_t> wire;
  for (NucleusTrack& t : tracks) {
    t.time = {static_cast<int64_t>(rng() % 2'000'000'000'000'000'000) / 1000 * 1000,
              rng() % 2 == 0};
    t.bottom = rng() % 2 == 0;
    for (size_t i = 0; i < 3; ++i) {
      t.velocity_valid[i] = rng() % 4 != 0;
      t.velocity_mps[i] = t.velocity_valid[i] ? v(rng) : -32.768;
      t.beam_distance_m[i] = r(rng);
    }
    const std::vector<uint8_t> b = encode_nucleus_packet(nucleus_track_packet(t));
    wire.insert(wire.end(), b.begin(), b.end());
  }
  const Parsed p = parse(wire, rng() | 1);
  EXPECT_EQ(p.counters.checksum_failures, 0u);
  EXPECT_EQ(p.counters.skipped_bytes, 0u);
  ASSERT_EQ(p.tracks.size(), tracks.size());
  for (size_t k = 0; k < tracks.size(); ++k) {
    const NucleusTrack &a = tracks[k], &b = p.tracks[k];
    EXPECT_EQ(b.time.device_ns, a.time.device_ns);
    EXPECT_EQ(b.time.posix, a.time.posix);
    EXPECT_EQ(b.bottom, a.bottom);
    EXPECT_EQ(b.velocity_valid, a.velocity_valid);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_FLOAT_EQ(static_cast<float>(b.velocity_mps[i]), static_cast<float>(a.velocity_mps[i]));
      EXPECT_FLOAT_EQ(static_cast<float>(b.beam_distance_m[i]),
                      static_cast<float>(a.beam_distance_m[i]));
    }
  }
  NucleusPacket huge{kNucleusBottomTrack, std::vector<uint8_t>(kNucleusMaxPayload + 1)};
  EXPECT_THROW(encode_nucleus_packet(huge), Error);
}

// The AHRS and altimeter records and every record's clock on Nortek's recording: each AHRS
// quaternion a unit one, its angles within their ranges, the clock never going back within a
// record type, every altimeter record decoded.
TEST(NucleusStream, AhrsAltimeterAndClockOfNortekRecording) {
  NucleusStream stream;
  const std::vector<uint8_t> bytes = nucleus_recording();
  std::vector<NucleusAhrs> ahrs;
  std::vector<NucleusAltimeter> altimeter;
  std::map<uint8_t, int64_t> last_ns;
  size_t went_back = 0, posix = 0, packets = 0;
  for (const NucleusPacket& p : stream.feed(bytes)) {
    const auto time = nucleus_time(p);
    ASSERT_TRUE(time.has_value());
    ++packets;
    posix += time->posix;
    if (last_ns.count(p.record_id) && time->device_ns < last_ns[p.record_id]) ++went_back;
    last_ns[p.record_id] = time->device_ns;
    if (const auto a = decode_nucleus_ahrs(p)) ahrs.push_back(*a);
    if (const auto a = decode_nucleus_altimeter(p)) altimeter.push_back(*a);
  }
  EXPECT_EQ(went_back, 0u);
  ASSERT_EQ(ahrs.size(), 1915u);
  ASSERT_EQ(altimeter.size(), 96u);
  for (const NucleusAhrs& a : ahrs) {
    double norm2 = 0;
    for (const double q : a.quaternion_wxyz) norm2 += q * q;
    EXPECT_NEAR(norm2, 1.0, 1e-3);
    EXPECT_LE(std::abs(a.roll_deg), 180.0);
    EXPECT_LE(std::abs(a.pitch_deg), 90.0);
    EXPECT_GE(a.heading_deg, 0.0);
    EXPECT_LT(a.heading_deg, 360.0);
    EXPECT_TRUE(std::isfinite(a.depth_m));
  }
  const double span_s =
      static_cast<double>(ahrs.back().time.device_ns - ahrs.front().time.device_ns) * 1e-9;
  std::printf(
      "AHRS %zu over %.1f s (%.1f Hz), first roll %.2f pitch %.2f heading %.2f deg depth %.3f m; "
      "altimeter %zu, first %.3f m quality %u valid %d; %zu of %zu clocks POSIX\n",
      ahrs.size(), span_s, static_cast<double>(ahrs.size() - 1) / span_s, ahrs[0].roll_deg,
      ahrs[0].pitch_deg, ahrs[0].heading_deg, ahrs[0].depth_m, altimeter.size(),
      altimeter[0].distance_m, altimeter[0].quality, altimeter[0].valid(), posix, packets);
}

TEST(NucleusStream, ChecksumOfOddAndEvenLengths) {
  EXPECT_EQ(nucleus_checksum({}), 0xB58C);
  const uint8_t even[] = {0x01, 0x02, 0x03, 0x04};
  EXPECT_EQ(nucleus_checksum(even), (0xB58C + 0x0201 + 0x0403) & 0xFFFF);
  const uint8_t odd[] = {0xFF, 0xFF, 0x7F};
  EXPECT_EQ(nucleus_checksum(odd), (0xB58C + 0xFFFF + 0x7F00) & 0xFFFF);
}

// A valid bottom-track packet with the X, Y and Z velocities flagged valid.
std::vector<uint8_t> bottom_track_packet(float vx) {
  std::vector<uint8_t> payload(128, 0);
  const uint32_t status = 0x7u << 9;
  for (int i = 0; i < 4; ++i) payload[12 + static_cast<size_t>(i)] = (status >> (8 * i)) & 0xFF;
  const float values[] = {vx, 0.25f, -0.125f};
  for (size_t i = 0; i < 3; ++i) {
    uint32_t bits = 0;
    std::memcpy(&bits, &values[i], 4);
    for (size_t k = 0; k < 4; ++k) payload[96 + 4 * i + k] = (bits >> (8 * k)) & 0xFF;
  }
  std::vector<uint8_t> p = {
      kNucleusSync, kNucleusHeaderSize, kNucleusBottomTrack, kNucleusFamily, 128, 0};
  const uint16_t data = nucleus_checksum(payload);
  p.push_back(static_cast<uint8_t>(data & 0xFF));
  p.push_back(static_cast<uint8_t>(data >> 8));
  const uint16_t header = nucleus_checksum({p.data(), 8});
  p.push_back(static_cast<uint8_t>(header & 0xFF));
  p.push_back(static_cast<uint8_t>(header >> 8));
  p.insert(p.end(), payload.begin(), payload.end());
  return p;
}

TEST(NucleusStream, RepliesNoiseAndCorruptPacketsArePassedOverAndCounted) {
  const std::string reply = "OK\r\nGETBT,DVL\r\n";
  std::vector<uint8_t> bytes(reply.begin(), reply.end());
  const auto good = bottom_track_packet(0.5f);
  bytes.insert(bytes.end(), good.begin(), good.end());
  auto corrupt = bottom_track_packet(0.75f);
  corrupt[50] ^= 0x10;  // a payload bit flipped on the line
  bytes.insert(bytes.end(), corrupt.begin(), corrupt.end());
  const auto last = bottom_track_packet(1.0f);
  bytes.insert(bytes.end(), last.begin(), last.end());
  const Parsed p = parse(bytes, 5);
  ASSERT_EQ(p.tracks.size(), 2u);
  EXPECT_TRUE(p.tracks[0].valid());
  EXPECT_NEAR(p.tracks[0].velocity_mps[0], 0.5, 1e-7);
  EXPECT_NEAR(p.tracks[0].velocity_mps[1], 0.25, 1e-7);
  EXPECT_NEAR(p.tracks[1].velocity_mps[0], 1.0, 1e-7);
  EXPECT_EQ(p.counters.packets, 2u);
  EXPECT_EQ(p.counters.checksum_failures, 1u);
  // The reply and the corrupt packet's bytes (all but those of a sync inside it, none here).
  EXPECT_EQ(p.counters.skipped_bytes, reply.size() + corrupt.size());
  // Another record or a short payload is no track.
  EXPECT_FALSE(decode_nucleus_track({kNucleusAhrs, std::vector<uint8_t>(128)}));
  EXPECT_FALSE(decode_nucleus_track({kNucleusBottomTrack, std::vector<uint8_t>(100)}));
}

}  // namespace
}  // namespace pensight::drivers
