// NucleusDvl against Nortek's own recording served by a stand-in on loopback, and the DvlSample of
// a track record.
#include "drivers/nucleus_dvl.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/fake_serial_device.h"
#include "tests/support/loopback_server.h"
#include "tests/support/nucleus_recording.h"

namespace pensight::drivers {
namespace {

using testing::nucleus_recording;

TEST(NucleusDvl, TrackRecordIntoTheBodyWithItsBeams) {
  NucleusTrack t;
  t.velocity_mps = {0.3, -0.1, 0.05};
  t.velocity_valid = {true, true, true};
  t.beam_distance_m = {1.2, 0.0, 1.4};  // the second beam without a return
  Eigen::Matrix3d R_B_S;                // the DVL looking forward: its Z along the body's x
  R_B_S << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  const DvlSample s = to_dvl_sample(t, R_B_S, 7);
  EXPECT_EQ(s.timestamp_ns, 7);
  EXPECT_TRUE(s.valid);
  EXPECT_TRUE(s.velocity_B_mps.isApprox(Eigen::Vector3d(0.05, -0.1, -0.3)));
  EXPECT_DOUBLE_EQ(s.beam_range_m[0], 1.2);
  EXPECT_TRUE(std::isnan(s.beam_range_m[1]));
  EXPECT_DOUBLE_EQ(s.beam_range_m[2], 1.4);
  EXPECT_TRUE(std::isnan(s.beam_range_m[3]));
  t.velocity_valid[1] = false;
  EXPECT_FALSE(to_dvl_sample(t, R_B_S, 7).valid);
  t.velocity_valid[1] = true;
  t.bottom = false;
  EXPECT_FALSE(to_dvl_sample(t, R_B_S, 7).valid);
}

// Nortek's bench recording (2,585 packets: 287 bottom track, 287 water track, 2,011 others, every
// velocity flagged invalid) served over TCP in two connections, the first cut mid-packet: the
// samples of both, none valid, in order.
TEST(NucleusDvl, NortekRecordingOverTcpAcrossADrop) {
  const std::vector<uint8_t> bytes = nucleus_recording();
  ASSERT_GT(bytes.size(), 100000u);
  testing::LoopbackServer nucleus;
  const size_t cut = bytes.size() / 2 + 3;  // inside a packet: its first part is lost
  std::thread server([&] {
    int c = nucleus.accept_one();
    testing::LoopbackServer::send_all(c, std::span(bytes).first(cut));
    ::close(c);
    c = nucleus.accept_one();
    testing::LoopbackServer::send_all(c, std::span(bytes).subspan(cut));
    testing::LoopbackServer::read_line(c);  // until the client closes
    ::close(c);
  });
  NucleusDvlConfig config;
  config.host = "127.0.0.1";
  config.port = nucleus.port();
  config.tcp.reconnect_delay_s = 0.05;
  std::vector<DvlSample> samples;
  {
    NucleusDvl dvl(config);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (dvl.connection_counters().connects < 2 ||
           dvl.connection_counters().bytes_received < bytes.size()) {
      if (std::chrono::steady_clock::now() > deadline) break;
      for (const DvlSample& s : dvl.poll(0.05)) samples.push_back(s);
    }
    for (int i = 0; i < 10; ++i) {
      for (const DvlSample& s : dvl.poll(0.01)) samples.push_back(s);
    }
    EXPECT_EQ(dvl.connection_counters().connects, 2u);
    EXPECT_EQ(dvl.connection_counters().drops, 1u);
    EXPECT_EQ(dvl.stream_counters().checksum_failures, 0u);
    // One packet is cut by the drop: at most one record of each kind is lost.
    EXPECT_GE(dvl.counters().samples, 286u);
    EXPECT_LE(dvl.counters().samples, 287u);
    EXPECT_GE(dvl.counters().water_track_skipped, 286u);
    EXPECT_GE(dvl.counters().other_records, 2010u);
    EXPECT_EQ(
        dvl.counters().samples + dvl.counters().water_track_skipped + dvl.counters().other_records,
        dvl.stream_counters().packets);
    EXPECT_GE(dvl.stream_counters().packets, 2584u);
  }
  server.join();
  ASSERT_EQ(samples.size(), samples.size() > 286 ? 287u : 286u);
  // Served at once, far faster than the device's clock runs (a record every 0.5 s of it), each
  // record is stamped at its arrival: the clock mapping never puts a sample after its arrival.
  for (size_t i = 0; i < samples.size(); ++i) {
    EXPECT_FALSE(samples[i].valid) << i;  // the recording's velocities are all flagged invalid
    if (i > 0) {
      EXPECT_GE(samples[i].timestamp_ns, samples[i - 1].timestamp_ns) << i;
    }
  }
}

// With start, on its command port: the stand-in asks for the password, answers STOP, SETCLOCKSTR,
// SETBT (bottom-track settings given) and START as a Nucleus does, then streams Nortek's recording
// on the same connection.
TEST(NucleusDvl, StartedOnItsCommandPort) {
  const std::vector<uint8_t> bytes = nucleus_recording();
  testing::LoopbackServer nucleus;
  std::vector<std::string> commands;
  std::thread server([&] {
    const int c = nucleus.accept_one();
    testing::LoopbackServer::send_all(c, std::string("Please enter password:\r\n"));
    commands.push_back(testing::LoopbackServer::read_line(c));
    testing::LoopbackServer::send_all(c, std::string("\r\nWelcome to Nortek Nucleus1000\r\n"));
    for (int i = 0; i < 4; ++i) {
      commands.push_back(testing::LoopbackServer::read_line(c));
      testing::LoopbackServer::send_all(c, std::string("OK\r\n"));
    }
    testing::LoopbackServer::send_all(c, bytes);
    testing::LoopbackServer::read_line(c);  // until the client closes
    ::close(c);
  });
  NucleusDvlConfig config;
  config.host = "127.0.0.1";
  config.port = nucleus.port();
  config.start = true;
  config.command.bottom_track = NucleusBottomTrack{.mode = "AUTO"};
  {
    NucleusDvl dvl(config);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (dvl.counters().samples < 287 && std::chrono::steady_clock::now() < deadline)
      dvl.poll(0.05);
    EXPECT_EQ(dvl.counters().samples, 287u);
    EXPECT_EQ(dvl.counters().water_track_skipped, 287u);
    EXPECT_EQ(dvl.stream_counters().skipped_bytes, 0u);
    EXPECT_EQ(dvl.stream_counters().checksum_failures, 0u);
    EXPECT_EQ(dvl.command_counters().starts, 1u);
    EXPECT_EQ(dvl.command_counters().failures, 0u) << dvl.last_command_error();
  }
  server.join();
  ASSERT_EQ(commands.size(), 5u);
  EXPECT_EQ(commands[0], "nortek\r");
  EXPECT_EQ(commands[1], "STOP\r");
  EXPECT_EQ(commands[2].rfind("SETCLOCKSTR,TIME=\"", 0), 0u) << commands[2];
  EXPECT_EQ(commands[3], "SETBT,MODE=\"AUTO\",WT=\"OFF\",DS=\"ON\"\r");
  EXPECT_EQ(commands[4], "START\r");
}

// The same stream on a serial line (a pseudo-terminal for the UART): the first 40 kB of the
// recording, every track record among them decoded.
TEST(NucleusDvl, NortekRecordingOnASerialLine) {
  const std::vector<uint8_t> bytes = nucleus_recording();
  ASSERT_GT(bytes.size(), 40000u);
  testing::FakeSerialDevice nucleus;
  NucleusDvlConfig config;
  config.serial_device = nucleus.path();
  config.serial.baud = 921600;
  NucleusDvl dvl(config);
  EXPECT_TRUE(dvl.poll(0.05).empty());  // opens the line
  const std::string part(bytes.begin(), bytes.begin() + 40000);
  size_t samples = 0;
  for (size_t at = 0; at < part.size(); at += 2000) {
    nucleus.send(part.substr(at, 2000));
    for (int i = 0; i < 3; ++i) samples += dvl.poll(0.02).size();
  }
  for (int i = 0; i < 10; ++i) samples += dvl.poll(0.02).size();
  EXPECT_EQ(dvl.connection_counters().bytes_received, part.size());
  EXPECT_EQ(dvl.stream_counters().checksum_failures, 0u);
  EXPECT_GT(samples, 0u);
  EXPECT_EQ(samples, dvl.counters().samples);
  EXPECT_EQ(
      dvl.counters().samples + dvl.counters().water_track_skipped + dvl.counters().other_records,
      dvl.stream_counters().packets);
}

}  // namespace
}  // namespace pensight::drivers
