// Endpoints and VehicleLink over UDP on 127.0.0.1 with ephemeral ports, on a simulated clock.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <optional>
#include <thread>

#include "core/error.h"
#include "mavlink/endpoint.h"
#include "mavlink/vehicle_link.h"
#include "tests/support/loopback_server.h"

namespace pensight::mavlink {
namespace {

constexpr int64_t kMs = 1'000'000;

std::string endpoint_error(const std::string& text) {
  try {
    parse_endpoint(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// Loopback delivery may lag a send by a moment: retries `done` for up to two seconds.
bool eventually(const std::function<bool()>& done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

// The vehicle's end: a udpin socket that collects our frames and answers as ArduSub would.
struct FakeVehicle {
  UdpSocket socket{parse_endpoint("udpin:127.0.0.1:0")};
  FrameParser parser;
  std::vector<Frame> frames;

  std::string endpoint() const { return "udpout:127.0.0.1:" + std::to_string(socket.local_port()); }
  void read() {
    std::vector<uint8_t> bytes;
    socket.receive(bytes);
    for (Frame& f : parser.feed(bytes)) frames.push_back(std::move(f));
  }
  template <class M>
  void send(const M& m, uint8_t sysid = 1, uint8_t compid = 1) {
    ASSERT_TRUE(socket.send(encode_frame(make_frame(m, 0, sysid, compid))));
  }
  template <class M>
  std::vector<M> received() const {
    std::vector<M> out;
    for (const Frame& f : frames) {
      if (f.msgid == M::kId) out.push_back(unpack<M>(f.payload));
    }
    return out;
  }
};

TEST(MavlinkEndpoint, ParsesMavproxyNotation) {
  const Endpoint out = parse_endpoint("udpout:127.0.0.1:14550");
  EXPECT_EQ(out.kind, Endpoint::Kind::kUdpOut);
  EXPECT_EQ(out.ipv4, 0x7F000001u);
  EXPECT_EQ(out.port, 14550);
  const Endpoint in = parse_endpoint("udpin:0.0.0.0:0");
  EXPECT_EQ(in.kind, Endpoint::Kind::kUdpIn);
  EXPECT_EQ(in.ipv4, 0u);
  EXPECT_EQ(parse_endpoint("udpout:localhost:5760").ipv4, 0x7F000001u);
}

TEST(MavlinkEndpoint, RefusesMalformedEndpointsNamingThem) {
  for (const std::string bad :
       {"tcp:127.0.0.1:0", "udp:127.0.0.1:14550", "udpout", "udpout:127.0.0.1",
        "udpout:127.0.0.1:", "udpout:127.0.0.1:0", "udpout:127.0.0.1:65536",
        "udpout:127.0.0.1:14x50", "udpout::14550", "udpout:host..invalid:14550", ""}) {
    const std::string e = endpoint_error(bad);
    EXPECT_NE(e.find("'" + bad + "'"), std::string::npos) << e;
    EXPECT_NE(e.find("udpout:HOST:PORT"), std::string::npos) << e;
  }
  EXPECT_NE(endpoint_error("udp:1.2.3.4:5").find("unknown scheme 'udp'"), std::string::npos);
  EXPECT_NE(endpoint_error("tcp:127.0.0.1:0").find("tcp:HOST:PORT"), std::string::npos);
  const Endpoint tcp = parse_endpoint("tcp:localhost:5777");
  EXPECT_EQ(tcp.kind, Endpoint::Kind::kTcp);
  EXPECT_EQ(tcp.host, "localhost");
  EXPECT_EQ(tcp.port, 5777);
  EXPECT_NE(endpoint_error("udpout:host..invalid:1").find("does not resolve"), std::string::npos);
  EXPECT_THROW(VehicleLink({.endpoint = "udpout:127.0.0.1"}), Error);
}

// Ten seconds of a 100 Hz loop, commands set for the first 1.2 s only: HEARTBEAT at 1 Hz,
// MANUAL_CONTROL at 10 Hz, the command while fresh and then the watchdog's neutral command.
TEST(MavlinkVehicleLink, SendsAtItsRatesAndTheWatchdogGoesNeutral) {
  FakeVehicle vehicle;
  VehicleLink link({.endpoint = vehicle.endpoint(), .role = LinkRole::kCompanionComputer});
  for (int64_t t = 0; t < 10'000 * kMs; t += 10 * kMs) {
    if (t < 1200 * kMs) link.set_manual_control(300, -2000, 800, 999, t, 0x5);
    link.poll(t);
    vehicle.read();
  }
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return vehicle.frames.size() >= 110;
  }));
  const auto heartbeats = vehicle.received<Heartbeat>();
  const auto controls = vehicle.received<ManualControl>();
  ASSERT_EQ(heartbeats.size(), 10u);
  ASSERT_EQ(controls.size(), 100u);
  EXPECT_EQ(heartbeats[0].type, kMavTypeOnboardController);
  EXPECT_EQ(heartbeats[0].autopilot, kMavAutopilotInvalid);
  EXPECT_EQ(heartbeats[0].mavlink_version, 3);
  EXPECT_EQ(vehicle.frames[0].sysid, 1);
  EXPECT_EQ(vehicle.frames[0].compid, kCompIdOnboardComputer);
  // The last command is stamped 1190 ms: those sent at 0, 100, ..., 1600 ms are fresh, from 1700
  // ms on (510 ms later) the watchdog's.
  for (size_t i = 0; i < controls.size(); ++i) {
    const bool fresh = i < 17;
    EXPECT_EQ(controls[i].x, fresh ? 300 : 0) << i;
    EXPECT_EQ(controls[i].y, fresh ? -1000 : 0) << i;
    EXPECT_EQ(controls[i].z, fresh ? 800 : 500) << i;
    EXPECT_EQ(controls[i].r, fresh ? 999 : 0) << i;
    EXPECT_EQ(controls[i].buttons, fresh ? 5 : 0) << i;
    EXPECT_EQ(controls[i].target, 1) << i;
  }
  const LinkCounters c = link.counters();
  EXPECT_EQ(c.neutral_commands, 83u);
  EXPECT_EQ(c.frames_sent, 110u);
  EXPECT_EQ(c.send_errors, 0u);
}

TEST(MavlinkVehicleLink, DecodesTheVehicleAndCommandsIt) {
  FakeVehicle vehicle;
  VehicleLink link({.endpoint = vehicle.endpoint()});
  link.poll(0);  // our first heartbeat tells the vehicle where we are
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return !vehicle.frames.empty();
  }));
  EXPECT_EQ(vehicle.frames[0].sysid, 255);
  EXPECT_EQ(vehicle.frames[0].compid, kCompIdMissionPlanner);
  EXPECT_EQ(vehicle.received<Heartbeat>().at(0).type, kMavTypeGcs);
  vehicle.send(Heartbeat{.custom_mode = 2, .type = 12, .autopilot = 3, .base_mode = 0x81});
  vehicle.send(Attitude{.time_boot_ms = 1234, .roll_rad = 0.1f, .yaw_rad = -3.0f});
  vehicle.send(ScaledPressure{.press_abs_hpa = 1003.5f, .temperature_cdeg = 2850});
  vehicle.send(ScaledPressure2{.press_abs_hpa = 1113.25f, .temperature_cdeg = 1525});
  vehicle.send(Heartbeat{.base_mode = 0}, 1, 100);  // a camera: not the vehicle
  ASSERT_TRUE(eventually([&] {
    link.poll(50 * kMs);
    return link.counters().parse.frames == 5;
  }));
  const VehicleStatus& s = link.status();
  EXPECT_EQ(s.heartbeat_ns, 50 * kMs);
  EXPECT_TRUE(s.armed);
  EXPECT_EQ(s.custom_mode, static_cast<uint32_t>(SubMode::kAltHold));
  EXPECT_EQ(s.attitude_ns, 50 * kMs);
  EXPECT_EQ(s.attitude.time_boot_ms, 1234u);
  EXPECT_FLOAT_EQ(s.attitude.roll_rad, 0.1f);
  EXPECT_FLOAT_EQ(s.attitude.yaw_rad, -3.0f);
  EXPECT_EQ(s.pressure_ns[0], 50 * kMs);
  EXPECT_FLOAT_EQ(s.pressure[0].press_abs_hpa, 1003.5f);
  EXPECT_EQ(s.pressure_ns[1], 50 * kMs);
  EXPECT_FLOAT_EQ(s.pressure[1].press_abs_hpa, 1113.25f);
  EXPECT_EQ(s.pressure[1].temperature_cdeg, 1525);
  EXPECT_EQ(s.pressure_ns[2], -1);
  EXPECT_EQ(link.counters().other_senders, 1u);

  ASSERT_TRUE(link.arm(true));
  ASSERT_TRUE(link.set_mode(SubMode::kPosHold));
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return vehicle.received<SetMode>().size() == 1;
  }));
  const auto arm = vehicle.received<CommandLong>().at(0);
  EXPECT_EQ(arm.command, kCmdComponentArmDisarm);
  EXPECT_EQ(arm.param[0], 1.0f);
  EXPECT_EQ(arm.target_system, 1);
  EXPECT_EQ(arm.target_component, kCompIdAutopilot);
  const auto mode = vehicle.received<SetMode>().at(0);
  EXPECT_EQ(mode.custom_mode, 16u);
  EXPECT_EQ(mode.base_mode, kModeFlagCustomModeEnabled);
  EXPECT_EQ(mode.target_system, 1);

  ASSERT_TRUE(link.request_message_rate(ScaledPressure2::kId, 5.0));
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return vehicle.received<CommandLong>().size() == 2;
  }));
  const auto rate = vehicle.received<CommandLong>().at(1);
  EXPECT_EQ(rate.command, kCmdSetMessageInterval);
  EXPECT_EQ(rate.param[0], 137.0f);
  EXPECT_EQ(rate.param[1], 200000.0f);  // the interval in microseconds
  EXPECT_EQ(rate.target_system, 1);
}

// ATTITUDE and the water's barometer become samples stamped at their own time_boot_ms (the vehicle
// booted 5 s before our clock's zero): the link's delay (here 3-9 ms) is removed down to its
// floor; the enclosure's air barometer gives no depth, and the water's none in its first
// max_age_s (2 s), while the automatic choice waits for every barometer to speak.
TEST(MavlinkVehicleLink, AttitudeAndDepthSamplesAtTheVehiclesOwnTimes) {
  FakeVehicle vehicle;
  VehicleLink link({.endpoint = vehicle.endpoint()});
  link.poll(0);
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return !vehicle.frames.empty();
  }));
  int64_t now_ns = 0;
  for (int k = 0; k < 40; ++k) {
    const auto boot_ms = static_cast<uint32_t>(5'000 + 100 * k);
    vehicle.send(Attitude{.time_boot_ms = boot_ms, .roll_rad = 0.01f * static_cast<float>(k)});
    if (k % 4 == 0) {
      vehicle.send(ScaledPressure{.time_boot_ms = boot_ms, .press_abs_hpa = 1003.5f});
      vehicle.send(ScaledPressure2{.time_boot_ms = boot_ms, .press_abs_hpa = 1113.77f});
    }
    const int64_t sent_ns = 100 * kMs * k;
    now_ns = sent_ns + (3 + 2 * (k % 4)) * kMs;
    const uint64_t expected = link.counters().parse.frames + (k % 4 == 0 ? 3 : 1);
    ASSERT_TRUE(eventually([&] {
      link.poll(now_ns);
      return link.counters().parse.frames == expected;
    }));
  }
  const std::vector<AttitudeSample> a = link.take_attitude_samples();
  ASSERT_EQ(a.size(), 40u);
  EXPECT_TRUE(link.take_attitude_samples().empty());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(a[k].roll_rad, 0.01 * static_cast<double>(k), 1e-6);
    // Stamped at time_boot_ms plus the smallest delay seen so far (3 ms from the first sample on).
    EXPECT_EQ(a[k].timestamp_ns, 100 * kMs * static_cast<int64_t>(k) + 3 * kMs) << k;
  }
  const std::vector<PressureSample> p = link.take_pressure_samples();
  ASSERT_EQ(p.size(), 5u);  // sent every 0.4 s, from 2 s after the first: 2.0 ... 3.6 s
  for (size_t k = 0; k < p.size(); ++k) {
    EXPECT_EQ(p[k].timestamp_ns, 400 * kMs * static_cast<int64_t>(k + 5) + 3 * kMs);
    EXPECT_NEAR(p[k].depth_m, 1.0, 1e-3);  // 100.52 hPa of sea water (1025 kg/m^3)
  }
  EXPECT_EQ(link.counters().samples_dropped, 0u);
}

// Over tcp:HOST:PORT (ArduSub SITL's 5760, BlueOS's 5777): the vehicle's frames in, ours out, and
// a new connection after the server closes one.
TEST(MavlinkVehicleLink, OverTcpReconnectingAfterTheServerCloses) {
  pensight::testing::LoopbackServer vehicle;
  VehicleLink link({.endpoint = "tcp:127.0.0.1:" + std::to_string(vehicle.port())});
  const auto frame_bytes = [](const Heartbeat& hb) {
    return encode_frame(make_frame(hb, 0, 1, kCompIdAutopilot));
  };
  std::thread server([&] {
    for (uint32_t mode : {2u, 19u}) {
      const int c = vehicle.accept_one();
      pensight::testing::LoopbackServer::send_all(c,
                                                  frame_bytes({.custom_mode = mode, .type = 12}));
      // Wait for our heartbeat before closing: the link answers on this connection.
      std::vector<uint8_t> got(64);
      pollfd p{c, POLLIN, 0};
      ::poll(&p, 1, 5000);
      EXPECT_GT(::recv(c, got.data(), got.size(), 0), 0);
      ::close(c);
    }
  });
  int64_t t = 0;
  ASSERT_TRUE(eventually([&] {
    link.poll(t += 100 * kMs);
    return link.status().custom_mode == 2;
  }));
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (link.status().custom_mode != 19 && std::chrono::steady_clock::now() < until) {
    link.poll(t += 100 * kMs);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  server.join();
  EXPECT_EQ(link.status().custom_mode, 19u);
  EXPECT_GE(link.counters().send_errors, 1u);  // the first connection's drop
  EXPECT_EQ(link.local_port(), 0);
}

TEST(MavlinkVehicleLink, RcOverrideUsesArduSubChannels) {
  FakeVehicle vehicle;
  VehicleLink link({.endpoint = vehicle.endpoint(), .rc_override = true});
  link.set_manual_control(1000, -500, 0, 250, 0);
  link.poll(0);
  link.poll(600 * kMs);  // the command is stale by now: neutral
  ASSERT_TRUE(eventually([&] {
    vehicle.read();
    return vehicle.received<RcChannelsOverride>().size() == 2;
  }));
  const auto rc = vehicle.received<RcChannelsOverride>();
  EXPECT_EQ(rc[0].chan_raw[4], 1900);  // forward
  EXPECT_EQ(rc[0].chan_raw[5], 1300);  // lateral
  EXPECT_EQ(rc[0].chan_raw[2], 1100);  // throttle
  EXPECT_EQ(rc[0].chan_raw[3], 1600);  // yaw
  EXPECT_EQ(rc[0].chan_raw[0], 0xFFFF) << "pitch left alone";
  EXPECT_EQ(rc[0].chan_raw[8], 0) << "channel 9 left alone";
  for (const size_t ch : {2, 3, 4, 5}) EXPECT_EQ(rc[1].chan_raw[ch], 1500) << ch;
  EXPECT_TRUE(vehicle.received<ManualControl>().empty());
}

// A ground station listening (udpin) and a companion computer sending to it (udpout) hear each
// other's heartbeats: the listener answers whoever sent to it last.
TEST(MavlinkVehicleLink, UdpinAndUdpoutLinksTalkToEachOther) {
  VehicleLink gcs({.endpoint = "udpin:127.0.0.1:0", .target_component = kCompIdOnboardComputer});
  VehicleLink companion({.endpoint = "udpout:127.0.0.1:" + std::to_string(gcs.local_port()),
                         .role = LinkRole::kCompanionComputer,
                         .target_system = 255,
                         .target_component = kCompIdMissionPlanner});
  int64_t t = 0;
  ASSERT_TRUE(eventually([&] {
    t += 1000 * kMs;
    companion.poll(t);
    gcs.poll(t);
    return gcs.status().heartbeat_ns >= 0 && companion.status().heartbeat_ns >= 0;
  }));
  EXPECT_EQ(gcs.counters().send_errors + companion.counters().send_errors, 0u);
}

TEST(MavlinkVehicleLink, AClosedPortCountsSendErrorsWithoutThrowing) {
  std::optional<FakeVehicle> gone(std::in_place);
  const std::string endpoint = gone->endpoint();
  gone.reset();  // nobody listens on that port any more
  VehicleLink link({.endpoint = endpoint});
  for (int64_t t = 0; t < 2000 * kMs; t += 10 * kMs) {
    EXPECT_NO_THROW(link.poll(t));
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  EXPECT_GT(link.counters().send_errors, 0u);
  EXPECT_LT(link.counters().frames_sent, 22u);
}

}  // namespace
}  // namespace pensight::mavlink
