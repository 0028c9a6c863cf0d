// VehicleLink against the real ArduSub (ArduPilot's SITL build in ../shared/sitl/ardusub, run as a
// separate program): its heartbeat, ATTITUDE at the rate we ask for with
// MAV_CMD_SET_MESSAGE_INTERVAL, and its three barometers, of which the one reading the water gives
// the depth of a vehicle at the surface. SITL sends on its SERIAL1 to our UDP port; a TCP client on
// SERIAL0 starts its main loop. Skipped where the SITL binary is absent.
#include <unistd.h>
#include <csignal>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "mavlink/vehicle_link.h"
#include "mavlink/water_depth.h"

namespace pensight::mavlink {
namespace {

namespace fs = std::filesystem;

// SITL instance 6: TCP 5820 (SERIAL0), away from a SITL a developer runs at the default 5760.
constexpr int kInstance = 6;

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

class ArduSubSitl : public ::testing::Test {
 protected:
  void SetUp() override {
    run_sh_ = fs::path(PENSIGHT_SHARED_DIR) / "sitl/ardusub/run.sh";
    if (!fs::exists(run_sh_) || !fs::exists(run_sh_.parent_path() / "bin/ardusub")) {
      GTEST_SKIP() << "ArduSub SITL not found at " << run_sh_.parent_path();
    }
    work_ = fs::temp_directory_path() / ("pensight-sitl-" + std::to_string(::getpid()));
    fs::create_directories(work_);
  }
  void TearDown() override {
    std::ifstream pid(work_ / "sitl.pid");
    if (long p = 0; pid >> p) ::kill(static_cast<pid_t>(p), SIGTERM);
    std::error_code ec;
    if (!work_.empty()) fs::remove_all(work_, ec);
  }

  // Starts SITL sending MAVLink on SERIAL1 to udp_port; true once it listens on SERIAL0 (TCP).
  bool start(uint16_t udp_port) {
    const std::string cmd = "INSTANCE=" + std::to_string(kInstance) + " '" + run_sh_.string() +
                            "' '" + work_.string() +
                            "' --bg --serial1 udpclient:127.0.0.1:" + std::to_string(udp_port) +
                            " > '" + (work_ / "run.log").string() + "' 2>&1";
    return std::system(cmd.c_str()) == 0;
  }

  fs::path run_sh_, work_;
};

// Two links at once, as a vehicle program beside a ground station: UDP on SERIAL1 (where the rates
// are asked for) and TCP on SERIAL0 (whose first client starts SITL's main loop), each at its own
// rates.
TEST_F(ArduSubSitl, AttitudeAtTheAskedRateAndTheDepthOfItsWaterBarometer) {
  VehicleLink link({.endpoint = "udpin:127.0.0.1:0"});
  ASSERT_TRUE(start(link.local_port())) << "SITL did not start; see its run.log";
  VehicleLink tcp_link({.endpoint = "tcp:127.0.0.1:" + std::to_string(5760 + 10 * kInstance)});
  const int64_t t0 = steady_ns();
  const auto poll_until = [&](double s, auto done) {
    while (steady_ns() - t0 < static_cast<int64_t>(s * 1e9) && !done()) {
      tcp_link.poll(steady_ns());
      link.poll(steady_ns());
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  };
  poll_until(30.0, [&] { return link.status().heartbeat_ns >= 0; });
  ASSERT_GE(link.status().heartbeat_ns, 0) << "no HEARTBEAT from ArduSub within 30 s";

  // ArduSub's default is 10 Hz ATTITUDE and 2 Hz barometers; ask for 25 Hz and 5 Hz.
  ASSERT_TRUE(link.request_message_rate(Attitude::kId, 25.0));
  ASSERT_TRUE(link.request_message_rate(ScaledPressure2::kId, 5.0));
  const double settle_s = static_cast<double>(steady_ns() - t0) * 1e-9 + 1.0;
  poll_until(settle_s, [] { return false; });
  link.take_attitude_samples();
  link.take_pressure_samples();
  tcp_link.take_attitude_samples();
  size_t tcp_attitudes = 0;
  std::vector<AttitudeSample> attitudes;
  std::vector<PressureSample> depths;
  const double window_s = 4.0;
  const int64_t from = steady_ns();
  int64_t worst_lag_ns = 0;
  while (steady_ns() - from < static_cast<int64_t>(window_s * 1e9)) {
    link.poll(steady_ns());
    tcp_link.poll(steady_ns());
    tcp_attitudes += tcp_link.take_attitude_samples().size();
    for (const AttitudeSample& a : link.take_attitude_samples()) {
      worst_lag_ns = std::max(worst_lag_ns, steady_ns() - a.timestamp_ns);
      attitudes.push_back(a);
    }
    for (const PressureSample& d : link.take_pressure_samples()) depths.push_back(d);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const double attitude_hz = static_cast<double>(attitudes.size()) / window_s;
  for (size_t i = 1; i < attitudes.size(); ++i) {
    EXPECT_GT(attitudes[i].timestamp_ns, attitudes[i - 1].timestamp_ns) << i;
  }
  const VehicleStatus& s = link.status();
  const WaterDepthParams params;
  const int water = water_pressure_index(s, params, steady_ns());
  ASSERT_GE(water, 0) << "no barometer heard";
  const double depth_m =
      depth_from_pressure_m(s.pressure[static_cast<size_t>(water)].press_abs_hpa, params);
  std::printf(
      "ArduSub SITL: ATTITUDE %.1f Hz (asked 25), each stamped at most %.1f ms before it was "
      "taken; barometers %.2f / %.2f / %.2f hPa, water = SCALED_PRESSURE%s, depth %.3f m, %zu "
      "depth samples\n",
      attitude_hz, static_cast<double>(worst_lag_ns) * 1e-6, s.pressure[0].press_abs_hpa,
      s.pressure[1].press_abs_hpa, s.pressure[2].press_abs_hpa,
      water == 0 ? "" : std::to_string(water + 1).c_str(), depth_m, depths.size());
  // Asked 25 Hz, ArduSub's scheduler gives 21.0 (its default is 10): the request is honoured.
  EXPECT_GE(attitude_hz, 15.0);
  EXPECT_LE(attitude_hz, 30.0);
  // The TCP link keeps ArduSub's default 10 Hz, rates being per link; SITL's serial ports also
  // model their baud rate, which thins the default streams (8.5 Hz measured).
  const double tcp_hz = static_cast<double>(tcp_attitudes) / window_s;
  std::printf("ArduSub SITL over TCP (SERIAL0): ATTITUDE %.1f Hz, heartbeat %s\n", tcp_hz,
              tcp_link.status().heartbeat_ns >= 0 ? "heard" : "not heard");
  EXPECT_GE(tcp_hz, 5.0);
  EXPECT_LE(tcp_hz, 13.0);
  EXPECT_EQ(tcp_link.counters().send_errors, 0u);
  EXPECT_EQ(tcp_link.counters().parse.bad_crc, 0u);
  EXPECT_TRUE(std::isfinite(s.attitude.roll_rad) && std::abs(s.attitude.roll_rad) < 0.5);
  EXPECT_TRUE(std::isfinite(s.attitude.yaw_rad));
  EXPECT_NE(water, 2) << "SITL's third barometer reads 0";
  std::printf("ArduSub SITL: SYS_STATUS battery %u mV, %d cA, %d %%, load %u permille\n",
              s.sys_status.voltage_battery_mv, s.sys_status.current_battery_ca,
              s.sys_status.battery_remaining_percent, s.sys_status.load_permille);
  EXPECT_GE(s.sys_status_ns, 0) << "no SYS_STATUS (ArduSub's default 2 Hz)";
  // SITL's simulated battery reads 12600 mV, 100 %.
  EXPECT_NEAR(s.sys_status.voltage_battery_mv, 12600, 500);
  EXPECT_GE(s.sys_status.battery_remaining_percent, 0);
  EXPECT_LE(s.sys_status.battery_remaining_percent, 100);
  // The vehicle floats at the surface (home altitude 0), its barometers below it: SITL's read
  // 1051.33 and 1033.58 hPa, 0.38 and 0.20 m of sea water.
  EXPECT_GT(depth_m, -0.1);
  EXPECT_LT(depth_m, 1.0);
  // The depth samples are the chosen barometer's (ArduSub's default 2 Hz for SCALED_PRESSURE), from
  // 2 s after the first barometer was heard (the automatic choice waits for all): 5 measured.
  ASSERT_GE(depths.size(), 3u);
  // The vehicle settles at the surface after SITL starts (measured 0.52, 0.48, 0.46 ... 0.38 m).
  for (const PressureSample& d : depths) {
    EXPECT_GT(d.depth_m, -0.1);
    EXPECT_LT(d.depth_m, 1.0);
  }
  EXPECT_NEAR(depths.back().depth_m, depth_m, 0.05);
  // Each attitude is stamped at its own time_boot_ms, taken within the 2 ms poll and the link's
  // delay of it.
  EXPECT_LT(worst_lag_ns, 100'000'000);
  EXPECT_EQ(link.counters().parse.bad_crc, 0u);
}

}  // namespace
}  // namespace pensight::mavlink
