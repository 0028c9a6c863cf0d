// The Nucleus's command session on its own: the replies as Nortek's nucleus_driver expects them
// (a password prompt, "Welcome to Nortek", "OK\r\n" / "ERROR\r\n"), split anywhere, a running
// Nucleus's records before STOP's reply, a refused password, a reply that never comes.
#include "drivers/nucleus_commands.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "core/timing.h"
#include "tests/support/nucleus_recording.h"

namespace pensight::drivers {
namespace {

constexpr int64_t kSecond = 1'000'000'000;

std::vector<uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

// feed(text) at now_ns.
NucleusCommandSession::Step feed(NucleusCommandSession& s, const std::string& text,
                                 int64_t now_ns = 0) {
  return s.feed(bytes_of(text), now_ns);
}

// The host's UTC that a SETCLOCKSTR command carries, in s since the Unix epoch; -1 if malformed.
int64_t clock_command_s(const std::string& command) {
  std::tm t{};
  char end[3] = {};
  if (std::sscanf(command.c_str(), "SETCLOCKSTR,TIME=\"%4d-%2d-%2d %2d:%2d:%2d\"%2c", &t.tm_year,
                  &t.tm_mon, &t.tm_mday, &t.tm_hour, &t.tm_min, &t.tm_sec, end) != 7 ||
      std::string(end, 2) != "\r\n") {
    return -1;
  }
  t.tm_year -= 1900;
  t.tm_mon -= 1;
  return static_cast<int64_t>(timegm(&t));
}

TEST(NucleusCommandSession, LogsInStopsSetsTheClockAndStartsOverTcp) {
  NucleusCommandSession s;
  EXPECT_EQ(s.restart(true, 0), "");
  EXPECT_EQ(feed(s, "Please enter pass").send, "");
  EXPECT_EQ(feed(s, "word:\r\n").send, "nortek\r\n");
  EXPECT_EQ(feed(s, "\r\nWelcome to Nortek Nucleus1000\r\n").send, "STOP\r\n");
  const std::string clock = feed(s, "OK\r\n").send;
  const int64_t now_s = host_now_ns() / kSecond;
  EXPECT_NEAR(static_cast<double>(clock_command_s(clock)), static_cast<double>(now_s), 2.0)
      << clock;
  EXPECT_EQ(feed(s, "O").send, "");
  EXPECT_EQ(feed(s, "K\r\n").send, "START\r\n");
  EXPECT_FALSE(s.streaming());
  const std::vector<uint8_t> records = testing::nucleus_recording();
  std::vector<uint8_t> reply = bytes_of("OK\r\n");
  reply.insert(reply.end(), records.begin(), records.begin() + 1000);
  const NucleusCommandSession::Step started = s.feed(reply, 0);
  EXPECT_TRUE(s.streaming());
  EXPECT_EQ(started.send, "");
  EXPECT_EQ(started.stream, std::vector<uint8_t>(records.begin(), records.begin() + 1000));
  // Streaming: every byte passes, "OK" or not.
  EXPECT_EQ(feed(s, "OK\r\n").stream, bytes_of("OK\r\n"));
  EXPECT_EQ(s.counters().starts, 1u);
  EXPECT_EQ(s.counters().failures, 0u);
}

// A serial line has no password; a Nucleus without one greets at once; a Nucleus still measuring
// from an earlier session streams records until STOP is answered, and those are not passed on.
TEST(NucleusCommandSession, SerialLineNoPasswordAndARunningNucleus) {
  NucleusCommandSession serial;
  EXPECT_EQ(serial.restart(false, 0), "STOP\r\n");

  NucleusCommandSession s;
  s.restart(true, 0);
  EXPECT_EQ(feed(s, "Welcome to Nortek\r\n").send, "STOP\r\n");
  const std::vector<uint8_t> records = testing::nucleus_recording();
  for (size_t at = 0; at < 20000; at += 700) {
    const std::vector<uint8_t> part(records.begin() + static_cast<std::ptrdiff_t>(at),
                                    records.begin() + static_cast<std::ptrdiff_t>(at + 700));
    const NucleusCommandSession::Step step = s.feed(part, 0);
    ASSERT_EQ(step.send, "") << at;
    EXPECT_TRUE(step.stream.empty());
  }
  EXPECT_EQ(feed(s, "OK\r\n").send.rfind("SETCLOCKSTR,TIME=\"", 0), 0u);
  EXPECT_EQ(feed(s, "ERROR\r\n").send, "START\r\n");  // the clock refused: started all the same
  EXPECT_EQ(s.counters().failures, 1u);
  EXPECT_NE(s.last_error().find("SETCLOCKSTR"), std::string::npos);
  feed(s, "OK\r\n");
  EXPECT_TRUE(s.streaming());
}

TEST(NucleusCommandSession, ARefusedPasswordIsSaidAndNotSentAgain) {
  NucleusCommandParams p;
  p.password = "secret";
  NucleusCommandSession s(p);
  s.restart(true, 0);
  EXPECT_EQ(feed(s, "Please enter password:\r\n").send, "secret\r\n");
  EXPECT_EQ(feed(s, "Please enter password:\r\n").send, "");
  EXPECT_EQ(s.counters().failures, 1u);
  EXPECT_NE(s.last_error().find("set dvl.password"), std::string::npos) << s.last_error();
  EXPECT_EQ(feed(s, "Please enter password:\r\n", 10 * kSecond).send, "");
  EXPECT_FALSE(s.streaming());
  // A new connection tries again.
  s.restart(true, 11 * kSecond);
  EXPECT_EQ(feed(s, "Please enter password:\r\n").send, "secret\r\n");
}

// A command without a reply within reply_timeout_s is sent again and counted; a port that never
// prompts (the data port named by mistake) is said, without the password in the message.
TEST(NucleusCommandSession, AReplyThatNeverComesIsCountedAndTheCommandSentAgain) {
  NucleusCommandSession s;
  s.restart(true, 0);
  EXPECT_EQ(feed(s, "", 1 * kSecond).send, "");
  EXPECT_EQ(feed(s, "", 3 * kSecond).send, "");
  EXPECT_EQ(s.counters().failures, 1u);
  EXPECT_NE(s.last_error().find("command port (9000)"), std::string::npos) << s.last_error();
  EXPECT_EQ(feed(s, "Please enter password:\r\n", 4 * kSecond).send, "nortek\r\n");
  EXPECT_EQ(feed(s, "", 7 * kSecond).send, "nortek\r\n");
  EXPECT_EQ(s.last_error().find("nortek"), std::string::npos) << s.last_error();
  EXPECT_EQ(feed(s, "Welcome to Nortek\r\n", 8 * kSecond).send, "STOP\r\n");
  EXPECT_EQ(feed(s, "", 9 * kSecond).send, "");
  EXPECT_EQ(feed(s, "", 10 * kSecond + 1).send, "STOP\r\n");
  EXPECT_EQ(s.counters().failures, 3u);
  EXPECT_NE(s.last_error().find("no reply to STOP"), std::string::npos) << s.last_error();
}

TEST(NucleusCommandSession, ARefusedStartIsSaid) {
  NucleusCommandSession s;
  s.restart(false, 0);
  feed(s, "OK\r\n");
  EXPECT_EQ(feed(s, "OK\r\n").send, "START\r\n");
  EXPECT_EQ(feed(s, "ERROR\r\n").send, "");
  EXPECT_FALSE(s.streaming());
  EXPECT_EQ(s.counters().failures, 1u);
  EXPECT_NE(s.last_error().find("START answered ERROR"), std::string::npos);
}

// Bottom-track settings go as SETBT between SETCLOCKSTR and START; a refused SETBT is said and
// the Nucleus is started with its own settings.
TEST(NucleusCommandSession, BottomTrackSettingsBeforeStart) {
  NucleusCommandSession s(
      {.bottom_track = NucleusBottomTrack{.mode = "AUTO", .velocity_range_mps = 2.5}});
  EXPECT_EQ(s.restart(false, 0), "STOP\r\n");
  EXPECT_GT(clock_command_s(feed(s, "OK\r\n").send), 0);
  EXPECT_EQ(feed(s, "OK\r\n").send, "SETBT,MODE=\"AUTO\",VR=2.5,WT=\"OFF\",DS=\"ON\"\r\n");
  EXPECT_EQ(feed(s, "OK\r\n").send, "START\r\n");
  feed(s, "OK\r\n");
  EXPECT_TRUE(s.streaming());
  EXPECT_EQ(s.counters().failures, 0u);

  NucleusCommandSession refused({.bottom_track = NucleusBottomTrack{.mode = "CRAWLER"}});
  refused.restart(false, 0);
  feed(refused, "OK\r\n");
  EXPECT_EQ(feed(refused, "OK\r\n").send, "SETBT,MODE=\"CRAWLER\",WT=\"OFF\",DS=\"ON\"\r\n");
  EXPECT_EQ(feed(refused, "ERROR\r\n").send, "START\r\n");
  EXPECT_EQ(refused.counters().failures, 1u);
  EXPECT_NE(refused.last_error().find("SETBT answered ERROR"), std::string::npos);
  feed(refused, "OK\r\n");
  EXPECT_TRUE(refused.streaming());
}

}  // namespace
}  // namespace pensight::drivers
