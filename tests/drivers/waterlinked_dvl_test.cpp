// WaterLinkedDvl against a stand-in DVL on loopback: the configuration sent on every connection,
// reports in the DVL's JSON, a malformed line and a water-track report among them, the connection
// closed by the DVL, then a DVL that stops answering without closing; and an address that does not
// resolve or does not listen.
#include "drivers/waterlinked_dvl.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "tests/support/fake_serial_device.h"
#include "tests/support/loopback_server.h"

namespace pensight::drivers {
namespace {

int64_t unix_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A velocity report as the DVL sends it, its ping 190 ms before it is sent.
std::string velocity_line(double vx, bool water = false) {
  const int64_t now = unix_us();
  return R"({"time":100.0,"vx":)" + std::to_string(vx) +
         R"(,"vy":0.0,"vz":0.0,"fom":0.001,"altitude":1.0,"transducers":[)"
         R"({"id":0,"velocity":0.0,"distance":1.1,"rssi":-30,"nsd":-90,"beam_valid":true}],)"
         R"("velocity_valid":true,"status":0,"format":"json_v3.1","type":")" +
         (water ? "velocity_water" : "velocity") + R"(","time_of_validity":)" +
         std::to_string(now - 190'000) + R"(,"time_of_transmission":)" + std::to_string(now) +
         "}\n";
}

using StandIn = testing::LoopbackServer;

TEST(WaterLinkedDvl, ReconnectsAfterACloseAndASilenceSendingItsConfigEachTime) {
  StandIn dvl;
  std::vector<std::string> commands;
  std::atomic<bool> done{false};
  std::thread server([&] {
    int c = dvl.accept_one();
    commands.push_back(StandIn::read_line(c));
    StandIn::send_all(c, R"({"response_to":"set_config","success":true,"error_message":"",)"
                         R"("result":null,"format":"json_v3.1","type":"response"})"
                         "\n");
    StandIn::send_all(c, velocity_line(0.1) + velocity_line(0.2) + "{\"type\":\"velocity\"\n" +
                             velocity_line(9.0, true) + velocity_line(0.3));
    ::close(c);  // the DVL closes the connection
    c = dvl.accept_one();
    commands.push_back(StandIn::read_line(c));
    StandIn::send_all(c, velocity_line(0.4) + velocity_line(0.5));
    const int silent = c;  // the DVL stops answering without closing
    c = dvl.accept_one();
    ::close(silent);
    commands.push_back(StandIn::read_line(c));
    StandIn::send_all(c, velocity_line(0.6));
    while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ::close(c);
  });

  WaterLinkedDvlConfig config;
  config.host = "127.0.0.1";
  config.port = dvl.port();
  config.set_config.dark_mode_enabled = true;
  config.tcp.idle_timeout_s = 0.3;
  config.tcp.reconnect_delay_s = 0.05;
  // The DVL looking forward: its Z along the body's x.
  config.R_B_S << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  WaterLinkedDvl source(config);
  std::vector<DvlSample> samples;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (samples.size() < 6 && std::chrono::steady_clock::now() < deadline) {
    for (const DvlSample& s : source.poll(0.05)) {
      samples.push_back(s);
      // The ping 190 ms before the report's transmission, on the same clock: stamped at the
      // ping, not at the arrival.
      const int64_t now_ns = unix_us() * 1000;
      EXPECT_GT(now_ns - s.timestamp_ns, 150'000'000);
      EXPECT_LT(now_ns - s.timestamp_ns, 1'000'000'000);
    }
  }
  done = true;
  server.join();
  ASSERT_EQ(samples.size(), 6u) << source.last_error();
  for (size_t i = 0; i < samples.size(); ++i) {
    EXPECT_TRUE(samples[i].valid);
    EXPECT_NEAR(samples[i].velocity_B_mps.z(), -0.1 * static_cast<double>(i + 1), 1e-9);
    EXPECT_DOUBLE_EQ(samples[i].beam_range_m[0], 1.1);
  }
  ASSERT_EQ(commands.size(), 3u);
  for (const std::string& c : commands) {
    EXPECT_EQ(c, R"({"command":"set_config","parameters":{"dark_mode_enabled":true}})");
  }
  EXPECT_EQ(source.connection_counters().connects, 3u);
  EXPECT_EQ(source.connection_counters().drops, 1u);
  EXPECT_EQ(source.connection_counters().idle_timeouts, 1u);
  EXPECT_EQ(source.stream_counters().malformed, 1u);
  EXPECT_EQ(source.counters().water_track_skipped, 1u);
  EXPECT_EQ(source.counters().samples, 6u);
}

TEST(WaterLinkedDvl, ARefusedConfigurationIsCountedAndNamed) {
  StandIn dvl;
  std::thread server([&] {
    const int c = dvl.accept_one();
    StandIn::read_line(c);
    StandIn::send_all(c, R"({"response_to":"set_config","success":false,)"
                         R"("error_message":"speed_of_sound out of range","result":null,)"
                         R"("format":"json_v3.1","type":"response"})"
                         "\n" +
                             velocity_line(0.1));
    StandIn::read_line(c);  // until the client closes
    ::close(c);
  });
  WaterLinkedDvlConfig config;
  config.host = "127.0.0.1";
  config.port = dvl.port();
  config.set_config.speed_of_sound_mps = 5000;
  {
    WaterLinkedDvl source(config);
    size_t n = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (n < 1 && std::chrono::steady_clock::now() < deadline) n += source.poll(0.05).size();
    EXPECT_EQ(n, 1u);
    EXPECT_EQ(source.counters().config_refused, 1u);
    EXPECT_EQ(source.last_error(), "the DVL refused set_config: speed_of_sound out of range");
  }
  server.join();
}

// On the serial line (a pseudo-terminal standing in for the UART): the configuration as a `wcs`
// sentence on opening, a ping sent both as wrz and the deprecated wrx taken once, a nak counted.
TEST(WaterLinkedDvl, OnTheSerialLine) {
  testing::FakeSerialDevice dvl;
  WaterLinkedDvlConfig config;
  config.serial_device = dvl.path();
  config.set_config.dark_mode_enabled = true;
  WaterLinkedDvl source(config);
  EXPECT_TRUE(source.poll(0.05).empty());
  const std::string wcs = waterlinked_set_config_sentence(config.set_config);
  EXPECT_EQ(dvl.receive(wcs.size()), wcs);
  dvl.send(
      waterlinked_sentence("wrn") +
      "wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,123.00,1*50\r\n"
      "wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0*d2\r\n"
      "wru,0,0.070,1.10,-40,-95*9c\r\n");
  std::vector<DvlSample> samples;
  for (int i = 0; i < 20 && samples.empty(); ++i) {
    for (const DvlSample& s : source.poll(0.1)) samples.push_back(s);
  }
  for (int i = 0; i < 3; ++i) source.poll(0.05);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_TRUE(samples[0].valid);
  EXPECT_NEAR(samples[0].velocity_B_mps.y(), -0.4, 1e-12);
  EXPECT_TRUE(std::isnan(samples[0].beam_range_m[0]));  // wru comes apart from the velocity
  EXPECT_EQ(source.stream_counters().superseded, 1u);
  EXPECT_EQ(source.counters().config_refused, 1u);
  EXPECT_EQ(source.last_error(), "the DVL refused set_config: wrn");
  EXPECT_EQ(source.connection_counters().connects, 1u);
}

TEST(WaterLinkedDvl, NoListenerIsCountedAndABadAddressNamed) {
  int port = 0;
  {
    StandIn closed;  // a port that was just free
    port = closed.port();
  }
  WaterLinkedDvlConfig config;
  config.host = "127.0.0.1";
  config.port = port;
  config.tcp.reconnect_delay_s = 0.05;
  WaterLinkedDvl source(config);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(source.poll(0.06).empty());
  EXPECT_GE(source.connection_counters().connect_failures, 2u);
  EXPECT_NE(source.last_error().find("Connection refused"), std::string::npos)
      << source.last_error();
  config.host = "no-such-dvl.invalid";
  try {
    WaterLinkedDvl bad(config);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("host 'no-such-dvl.invalid' does not resolve"),
              std::string::npos)
        << e.what();
  }
  config.host = "127.0.0.1";
  config.tcp.idle_timeout_s = 0;
  EXPECT_THROW(WaterLinkedDvl{config}, Error);
}

}  // namespace
}  // namespace pensight::drivers
