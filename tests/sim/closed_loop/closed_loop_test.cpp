#include "sim/closed_loop.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include "core/csv.h"
#include "core/error.h"
#include "mavlink/endpoint.h"
#include "mavlink/frame.h"
#include "mavlink/messages.h"
#include "pipeline/dataset/dataset_reader.h"
#include "sim/closed_loop_report.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::sim {
namespace {

std::filesystem::path source_dir() {
  const char* dir = std::getenv("PENSIGHT_SOURCE_DIR");
  return dir ? dir : ".";
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("pensight_closed_loop_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

Scenario short_hold(double seconds) {
  Scenario s = load_scenario(source_dir() / "scenarios/hold_0p5.yaml");
  s.duration_s = seconds;
  validate(s);
  return s;
}

// Two and a half seconds: the start-up, then the first commands. The files are there and in the
// contract's form, and the controller saw the net in every frame.
TEST(ClosedLoop, WritesTheDatasetAndClosedLoopCsv) {
  const Scenario s = short_hold(2.5);
  const auto out = fresh_dir("short");
  int on_step_calls = 0;
  ClosedLoopOptions options;
  options.on_step = [&](const ClosedLoopStep&) { ++on_step_calls; };
  const ClosedLoopSummary summary = run_closed_loop(s, out, options, testing::test_device());
  ASSERT_EQ(summary.steps.size(), 26u);
  EXPECT_EQ(on_step_calls, 26);
  for (const ClosedLoopStep& st : summary.steps) {
    EXPECT_NEAR(st.d_net_est_m, st.d_net_true_m, 0.02 * st.d_net_true_m) << st.t_s;
  }
  EXPECT_EQ(summary.steps.front().command.state, control::ControlState::kStartup);
  EXPECT_EQ(summary.steps.back().command.state, control::ControlState::kTracking);
  EXPECT_GT(summary.steps.back().command.x, 0);  // 0.3 m too far: forward

  const Dataset d = read_dataset(out);
  EXPECT_EQ(d.frames.size(), 26u);
  ASSERT_TRUE(d.groundtruth0.has_value());
  EXPECT_TRUE(d.groundtruth0->has_depth);
  ASSERT_TRUE(d.dvl0.has_value());
  EXPECT_GE(d.dvl0->samples.size(), 10u);

  const CsvTable csv(out / "closed_loop.csv", 25, 25);
  EXPECT_EQ(csv.rows(), 26u);
  for (const char* column : {"timestamp [ns]", "d_net_true [m]", "psi_net_true [rad]",
                             "d_net_est [m]", "psi_net_est [rad]", "d_ref [m]", "stick_x"}) {
    EXPECT_NE(std::find(csv.header().begin(), csv.header().end(), column), csv.header().end())
        << column;
  }
  EXPECT_TRUE(std::filesystem::is_regular_file(out / "closed_loop.html"));
}

TEST(ClosedLoop, RefusesAScenarioWithoutControlOrInColour) {
  Scenario s = short_hold(1);
  s.control.reset();
  const auto out = fresh_dir("refused");
  try {
    run_closed_loop(s, out, {}, testing::test_device());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("control:"), std::string::npos) << e.what();
  }
  s = short_hold(1);
  s.camera.colour = true;
  EXPECT_THROW(run_closed_loop(s, out, {}, testing::test_device()), Error);
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ClosedLoop, ScenarioControlSectionIsStrict) {
  const std::string base = R"(
trajectory: {waypoints: [{t_s: 0, along_m: 0, net_distance_m: 1, depth_m: 3}]}
)";
  const auto error_of = [&](const std::string& extra) -> std::string {
    try {
      parse_scenario(base + extra, "s.yaml");
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error_of("control: {legs: [{d_ref_m: 0.5}]}"), "(no error)");
  EXPECT_NE(error_of("control: {gains: {yaw: {kp: -1}}}").find("'control.gains.yaw.kp'"),
            std::string::npos);
  EXPECT_NE(error_of("control: {stratgy: dvl}").find("'control.stratgy'"), std::string::npos);
  EXPECT_NE(error_of("vehicle: {pilot_gain: 2}").find("vehicle"), std::string::npos);
  EXPECT_NE(error_of("vehicle: {pilot_gian: 0.5}").find("'vehicle.pilot_gian'"), std::string::npos);
}

// The CLI sends its commands to a ground station: arm, ALT_HOLD, HEARTBEAT every simulated second
// and MANUAL_CONTROL every step, from the companion computer's ids.
TEST(ClosedLoopCli, SendsItsCommandsOverMavlink) {
  mavlink::UdpSocket station(mavlink::parse_endpoint("udpin:127.0.0.1:0"));
  const auto out = fresh_dir("mavlink");
  const std::string command =
      std::string(PENSIGHT_CLI) + " closed-loop " +
      (source_dir() / "scenarios/hold_0p5.yaml").string() + " --out " + out.string() +
      " --duration 3 --quiet --mavlink udpout:127.0.0.1:" + std::to_string(station.local_port()) +
      " > " + (out.string() + ".log") + " 2>&1";
  int rc = -1;
  std::thread run([&] { rc = std::system(command.c_str()); });
  mavlink::FrameParser parser;
  std::map<uint32_t, int> count;
  std::vector<uint8_t> bytes;
  int sysid = -1, compid = -1;
  const auto drain = [&] {
    bytes.clear();
    station.receive(bytes);
    for (const mavlink::Frame& f : parser.feed(bytes)) {
      ++count[f.msgid];
      sysid = f.sysid;
      compid = f.compid;
    }
  };
  while (rc == -1) {
    drain();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  run.join();
  drain();
  ASSERT_EQ(rc, 0) << std::ifstream(out.string() + ".log").rdbuf();
  EXPECT_EQ(sysid, 1);
  EXPECT_EQ(compid, mavlink::kCompIdOnboardComputer);
  EXPECT_EQ(count[mavlink::Heartbeat::kId], 4);       // t = 0, 1, 2, 3 s of simulated time
  EXPECT_EQ(count[mavlink::ManualControl::kId], 31);  // every 0.1 s step
  EXPECT_EQ(count[mavlink::CommandLong::kId], 1);     // arm
  EXPECT_EQ(count[mavlink::SetMode::kId], 1);         // ALT_HOLD
  EXPECT_EQ(parser.counters().bad_crc, 0u);
}

}  // namespace
}  // namespace pensight::sim
