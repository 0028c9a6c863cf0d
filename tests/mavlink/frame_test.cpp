// The CRC, the messages' wire layout, frame encoding and the streaming parser.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "core/error.h"
#include "mavlink/crc.h"
#include "mavlink/frame.h"
#include "mavlink/messages.h"
#include "tests/mavlink/samples.h"

namespace pensight::mavlink {
namespace {

using Bytes = std::vector<uint8_t>;

// Feeds `bytes` in random chunks of 0..max_chunk bytes.
std::vector<Frame> feed_chunked(FrameParser& p, const Bytes& bytes, std::mt19937_64& rng,
                                size_t max_chunk) {
  std::vector<Frame> out;
  for (size_t at = 0; at < bytes.size();) {
    const size_t n = std::min(bytes.size() - at, static_cast<size_t>(rng() % (max_chunk + 1)));
    for (Frame& f : p.feed(std::span(bytes).subspan(at, n))) out.push_back(std::move(f));
    at += n;
  }
  return out;
}

TEST(MavlinkCrc, MatchesTheCrc16Mcrf4xxCheckValue) {
  const std::string_view check = "123456789";
  EXPECT_EQ(crc16({reinterpret_cast<const uint8_t*>(check.data()), check.size()}), 0x6F91);
}

TEST(MavlinkMessages, EveryMessageRoundTripsThroughAFrame) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  testing::for_each_message_type([&]<class M>(M) {
    const MessageInfo& info = *find_message(M::kId);
    for (int i = 0; i < 200; ++i) {
      const M sent = testing::random_message<M>(rng);
      const Frame frame = make_frame(sent, uint8_t(i), uint8_t(rng()), uint8_t(rng()));
      ASSERT_EQ(frame.payload.size(), info.length) << info.name;
      const Bytes bytes = encode_frame(frame);
      FrameParser parser;
      const auto got = parser.feed(bytes);
      ASSERT_EQ(got.size(), 1u) << info.name;
      EXPECT_EQ(got[0].msgid, M::kId);
      EXPECT_EQ(got[0].seq, frame.seq);
      EXPECT_EQ(got[0].sysid, frame.sysid);
      EXPECT_EQ(got[0].compid, frame.compid);
      EXPECT_EQ(got[0].payload, frame.payload) << info.name;
      EXPECT_EQ(testing::fields_of(unpack<M>(got[0].payload)), testing::fields_of(sent))
          << info.name;
    }
  });
}

TEST(MavlinkFrames, TrailingZerosAreCutAndZeroExtendedOnReceipt) {
  const Bytes hb =
      encode_frame(make_frame(Heartbeat{.custom_mode = 7, .mavlink_version = 0}, 0, 1, 1));
  EXPECT_EQ(hb[1], 1) << "only custom_mode's low byte is non-zero";
  EXPECT_EQ(hb.size(), 10u + 1 + 2);
  const Bytes empty = encode_frame(make_frame(Heartbeat{.mavlink_version = 0}, 0, 1, 1));
  EXPECT_EQ(empty[1], 1) << "the first payload byte is always kept";
  // MANUAL_CONTROL is 30 bytes with its extensions; target is the last non-zero one (offset 10).
  const Bytes mc = encode_frame(make_frame(ManualControl{.z = 500, .target = 1}, 0, 255, 190));
  EXPECT_EQ(mc[1], 11);
  FrameParser p;
  const auto got = p.feed(mc);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].payload.size(), 30u);
  const auto back = unpack<ManualControl>(got[0].payload);
  EXPECT_EQ(back.z, 500);
  EXPECT_EQ(back.target, 1);
  // unpack zero-extends a short payload itself, and refuses a long one.
  EXPECT_EQ(unpack<Heartbeat>(Bytes{0x10}).custom_mode, 0x10u);
  EXPECT_THROW(unpack<Heartbeat>(Bytes(10, 0)), Error);
  EXPECT_THROW(encode_frame(Frame{.msgid = 12345, .payload = {1}}), Error);
}

// Published frames from rust-mavlink's tests (mavlink/tests/test_shared/mod.rs and
// v2_encode_decode_tests.rs: HEARTBEAT_V2, COMMAND_LONG_TRUNCATED_V2), an implementation that
// shares no code with this one: decoded to their known fields and re-encoded byte for byte.
TEST(MavlinkFrames, PublishedFramesDecodeAndReencodeExactly) {
  const Bytes heartbeat = {0xfd, 0x09, 0x00, 0x00, 0xef, 0x01, 0x01, 0x00, 0x00, 0x00, 0x05,
                           0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03, 0x03, 0x10, 0xf0};
  Bytes command_long = {0xfd, 30, 0, 0, 0, 0, 50, 76, 0, 0, 0, 0, 230, 66, 0, 64, 156, 69};
  command_long.resize(command_long.size() + 20, 0);
  command_long.insert(command_long.end(), {255, 1, 188, 195});

  FrameParser p;
  auto frames = p.feed(heartbeat);
  ASSERT_EQ(frames.size(), 1u);
  const auto hb = unpack<Heartbeat>(frames[0].payload);
  EXPECT_EQ(frames[0].seq, 239);
  EXPECT_EQ(hb.custom_mode, 5u);
  EXPECT_EQ(hb.type, 2);       // MAV_TYPE_QUADROTOR
  EXPECT_EQ(hb.autopilot, 3);  // MAV_AUTOPILOT_ARDUPILOTMEGA
  EXPECT_EQ(hb.base_mode, 0x59);
  EXPECT_EQ(hb.system_status, 3);
  EXPECT_EQ(hb.mavlink_version, 3);
  EXPECT_EQ(encode_frame(make_frame(hb, 239, 1, 1)), heartbeat);

  frames = p.feed(command_long);
  ASSERT_EQ(frames.size(), 1u);
  const auto cmd = unpack<CommandLong>(frames[0].payload);
  EXPECT_EQ(cmd.command, 511);  // MAV_CMD_SET_MESSAGE_INTERVAL
  EXPECT_EQ(cmd.param[0], 115.0f);
  EXPECT_EQ(cmd.param[1], 5000.0f);
  EXPECT_EQ(cmd.target_system, 0);
  EXPECT_EQ(encode_frame(make_frame(cmd, 0, 0, 50)), command_long);
}

// A stream with one of each thing the parser must drop between good frames, fed whole and in
// random chunks: the same frames and exact counts either way.
TEST(MavlinkParser, DropsAndCountsBadInputAndResynchronises) {
  const Heartbeat hb{.custom_mode = 2, .type = 12, .autopilot = 3, .base_mode = 0x81};
  const Bytes good = encode_frame(make_frame(hb, 1, 1, 1));
  Bytes bad_crc = good;
  bad_crc[12] ^= 0x40;
  const Bytes truncated(good.begin(), good.begin() + 14);  // cut in the payload
  // v1: STX 0xFE, len, seq, sysid, compid, msgid, payload, CRC with the same CRC_EXTRA.
  Bytes v1 = {kStxV1, 9, 1, 1, 1, 0};
  v1.insert(v1.end(), good.begin() + 10, good.end() - 2);
  const uint16_t v1_crc = crc_accumulate(50, crc16(std::span(v1).subspan(1)));
  v1.insert(v1.end(), {uint8_t(v1_crc), uint8_t(v1_crc >> 8)});
  Bytes signed_frame = good;
  signed_frame[2] = kIncompatSigned;
  const uint16_t s_crc = crc_accumulate(50, crc16(std::span(signed_frame).subspan(1, 18)));
  signed_frame[19] = uint8_t(s_crc);
  signed_frame[20] = uint8_t(s_crc >> 8);
  signed_frame.insert(signed_frame.end(), kSignatureSize, 0x11);
  Bytes unknown = good;
  unknown[8] = 0x30;  // msgid 0x3000: not in the table, so skipped unchecked
  Bytes too_long = good;
  too_long[1] = 10;  // HEARTBEAT is 9 bytes at most
  const Bytes garbage = {0x00, 0x55, 0xAA, 0x13, 0x37};
  const Bytes unknown_flag = {kStxV2, 9, 0x02};

  Bytes stream;
  for (const Bytes* part : std::initializer_list<const Bytes*>{
           &good, &garbage, &good, &bad_crc, &good, &truncated, &good, &v1, &good, &signed_frame,
           &good, &unknown, &good, &too_long, &good, &unknown_flag, &good}) {
    stream.insert(stream.end(), part->begin(), part->end());
  }
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  for (const size_t max_chunk : {stream.size(), size_t{1}, size_t{7}, size_t{40}}) {
    FrameParser p;
    const auto frames = feed_chunked(p, stream, rng, max_chunk);
    ASSERT_EQ(frames.size(), 9u) << "chunks up to " << max_chunk;
    for (const Frame& f : frames) EXPECT_EQ(encode_frame(f), good);
    const ParseCounters& c = p.counters();
    EXPECT_EQ(c.frames, 9u);
    EXPECT_EQ(c.bad_crc, 2u) << "the corrupted frame and the truncated one";
    EXPECT_EQ(c.v1_frames, 1u);
    EXPECT_EQ(c.signed_frames, 1u);
    EXPECT_EQ(c.unknown_id, 1u);
    EXPECT_EQ(c.bad_length, 1u);
    EXPECT_EQ(c.garbage_bytes, garbage.size() + bad_crc.size() + truncated.size() +
                                   too_long.size() + unknown_flag.size());
    EXPECT_EQ(p.buffered(), 0u);
  }
}

// Random bytes with good frames among them, in random chunks: no crash, nothing invented, a
// bounded buffer, and the same result for any chunking.
TEST(MavlinkParser, SurvivesRandomBytes) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  Bytes stream;
  std::unordered_set<std::string> sent;  // the frames' bytes
  while (stream.size() < (1u << 20)) {
    for (uint64_t i = rng() % 200; i > 0; --i) stream.push_back(uint8_t(rng()));
    testing::for_each_message_type([&]<class M>(M) {
      if (rng() % 7 != 0) return;
      const Bytes f = encode_frame(make_frame(testing::random_message<M>(rng), 0, 1, 1));
      stream.insert(stream.end(), f.begin(), f.end());
      sent.emplace(f.begin(), f.end());
    });
  }
  FrameParser whole, chunked;
  const auto a = whole.feed(stream);
  const auto b = feed_chunked(chunked, stream, rng, 300);
  for (const Frame& f : a) {
    const Bytes bytes = encode_frame(f);
    EXPECT_TRUE(sent.contains(std::string(bytes.begin(), bytes.end())));
  }
  EXPECT_GT(a.size(), sent.size() * 9 / 10) << "of " << sent.size();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(encode_frame(a[i]), encode_frame(b[i]));
  EXPECT_EQ(whole.counters().garbage_bytes, chunked.counters().garbage_bytes);
  EXPECT_LT(chunked.buffered(), 281u);
}

}  // namespace
}  // namespace pensight::mavlink
