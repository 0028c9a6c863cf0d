// The camera URI and the record YAML: every accepted form, and each mistake named with its fix.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "live/camera_uri.h"
#include "live/record_config.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "tests/support/error_message.h"

namespace pensight::live {
namespace {
namespace fs = std::filesystem;

TEST(CameraUri, EveryFormAndItsTarget) {
  EXPECT_EQ(parse_camera_uri("v4l2:/dev/video0").kind, CameraUriKind::kV4l2);
  EXPECT_EQ(parse_camera_uri("v4l2:/dev/video0").target, "/dev/video0");
  const std::string blueos =
      "gst:udpsrc port=5600 ! application/x-rtp,payload=96 ! rtph264depay ! h264parse ! "
      "avdec_h264 ! videoconvert ! video/x-raw,format=GRAY8 ! appsink sync=false max-buffers=1 "
      "drop=true";
  EXPECT_EQ(parse_camera_uri(blueos).kind, CameraUriKind::kGstreamer);
  EXPECT_EQ(parse_camera_uri(blueos).target, blueos.substr(4));
  for (const char* url : {"rtsp://192.168.2.2:8554/video", "tcp://127.0.0.1:5600", "udp://@:5600",
                          "http://cam/stream.mjpg"}) {
    EXPECT_EQ(parse_camera_uri(url).kind, CameraUriKind::kNetwork) << url;
    EXPECT_EQ(parse_camera_uri(url).target, url);
  }
  EXPECT_EQ(parse_camera_uri("dataset:runs/dive1").kind, CameraUriKind::kDataset);
  EXPECT_EQ(parse_camera_uri("dataset:runs/dive1").target, "runs/dive1");
  EXPECT_EQ(parse_camera_uri("file:dive.mkv").target, "dive.mkv");
  EXPECT_EQ(parse_camera_uri("/data/dive:1.mkv").kind, CameraUriKind::kFile);
  EXPECT_EQ(parse_camera_uri("dive.mkv").target, "dive.mkv");
}

TEST(CameraUri, MistakesAreNamedWithTheAcceptedForms) {
  EXPECT_NE(testing::error_message([] { parse_camera_uri(""); }).find("empty (accepted: v4l2:"),
            std::string::npos);
  EXPECT_NE(testing::error_message([] {
              parse_camera_uri("gst:videotestsrc ! fakesink");
            }).find("must end in appsink"),
            std::string::npos);
  EXPECT_NE(testing::error_message([] { parse_camera_uri("usb:0"); }).find("unknown scheme 'usb:'"),
            std::string::npos);
  EXPECT_NE(
      testing::error_message([] { parse_camera_uri("dataset:"); }).find("nothing after 'dataset:'"),
      std::string::npos);
  EXPECT_NE(testing::error_message([] { parse_camera_uri("rtsp://"); }).find("no address"),
            std::string::npos);
}

class RecordConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pensight_live_config_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "calib");
    CameraCalibration cam;
    cam.camera.width_px = 720;
    cam.camera.height_px = 540;
    write("calib/cam0.yaml", camera_yaml(cam));
    DvlCalibration dvl;
    for (size_t i = 0; i < 4; ++i) dvl.beam_directions_S[i] = Eigen::Vector3d::UnitZ();
    write("calib/dvl0.yaml", dvl_yaml(dvl));
    SceneConfig scene;
    scene.bar_length_m = 0.025;
    write("calib/scene.yaml", scene_yaml(scene));
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& rel, const std::string& text) const {
    std::ofstream(dir_ / rel) << text;
  }
  RecordConfig parse(const std::string& text) const {
    return parse_record_config(text, "live.yaml", dir_);
  }
  fs::path dir_;
};

constexpr const char* kMinimal =
    "scene: calib/scene.yaml\ncamera:\n  uri: tcp://127.0.0.1:5600\n  calibration: "
    "calib/cam0.yaml\n";

TEST_F(RecordConfigTest, MinimalFileHasNoDvlNoLinkAndTheDefaults) {
  const RecordConfig c = parse(kMinimal);
  EXPECT_EQ(c.scene.bar_length_m, 0.025);
  EXPECT_EQ(c.camera.calibration.camera.width_px, 720);
  EXPECT_EQ(c.camera.source.latency_s, 0.0);
  EXPECT_EQ(c.camera.source.timeout_s, 2.0);
  EXPECT_FALSE(c.dvl);
  EXPECT_FALSE(c.mavlink);
}

TEST_F(RecordConfigTest, DvlAndLinkSectionsWithTheKindsDefaults) {
  const RecordConfig c = parse(std::string(kMinimal) +
                               "  latency_s: 0.15\ndvl:\n  kind: nucleus\n  calibration: "
                               "calib/dvl0.yaml\n  clock:\n    window_s: 20\nmavlink:\n  "
                               "endpoint: tcp:127.0.0.1:5777\n  water_depth:\n    "
                               "pressure_source: 2\n    water_density_kgpm3: 997\n");
  EXPECT_EQ(c.camera.source.latency_s, 0.15);
  ASSERT_TRUE(c.dvl);
  EXPECT_EQ(c.dvl->kind, DvlKind::kNucleus);
  EXPECT_EQ(c.dvl->host, "192.168.2.201");
  EXPECT_EQ(c.dvl->port, 9002);
  EXPECT_EQ(c.dvl->clock.window_s, 20);
  ASSERT_TRUE(c.mavlink);
  EXPECT_EQ(c.mavlink->endpoint, "tcp:127.0.0.1:5777");
  EXPECT_EQ(c.mavlink->water_depth.pressure_source, 2);
  EXPECT_EQ(c.mavlink->water_depth.water_density_kgpm3, 997);
  EXPECT_EQ(c.mavlink->attitude_rate_hz, 25);
  const RecordConfig w =
      parse(std::string(kMinimal) + "dvl:\n  kind: waterlinked\n  calibration: calib/dvl0.yaml\n");
  EXPECT_EQ(w.dvl->host, "192.168.194.95");
  EXPECT_EQ(w.dvl->port, 16171);
  EXPECT_TRUE(w.dvl->dark_mode);
  EXPECT_FALSE(c.dvl->start);
  // Started on its command port: 9000 and Nortek's default password unless given.
  const RecordConfig n = parse(std::string(kMinimal) +
                               "dvl:\n  kind: nucleus\n  start: true\n  calibration: "
                               "calib/dvl0.yaml\n");
  EXPECT_TRUE(n.dvl->start);
  EXPECT_EQ(n.dvl->port, 9000);
  EXPECT_EQ(n.dvl->nucleus_command.password, "nortek");
  EXPECT_EQ(parse(std::string(kMinimal) +
                  "dvl:\n  kind: nucleus\n  start: true\n  password: x1\n  port: 9100\n"
                  "  calibration: calib/dvl0.yaml\n")
                .dvl->nucleus_command.password,
            "x1");
  EXPECT_FALSE(n.dvl->nucleus_command.bottom_track);
}

// dvl.bottom_track: SETBT before every START, the mode in any case, the rest the Nucleus's own
// where not given; only where pensight starts a Nucleus.
TEST_F(RecordConfigTest, NucleusBottomTrackSettings) {
  const std::string nucleus = std::string(kMinimal) +
                              "dvl:\n  kind: nucleus\n  start: true\n  calibration: "
                              "calib/dvl0.yaml\n  bottom_track:\n";
  const RecordConfig c = parse(nucleus + "    mode: crawler\n    velocity_range_mps: 1.5\n");
  ASSERT_TRUE(c.dvl->nucleus_command.bottom_track);
  const drivers::NucleusBottomTrack& b = *c.dvl->nucleus_command.bottom_track;
  EXPECT_EQ(b.mode, "CRAWLER");
  EXPECT_EQ(b.velocity_range_mps, 1.5);
  EXPECT_FALSE(b.water_track);
  EXPECT_EQ(drivers::bottom_track_command(b),
            "SETBT,MODE=\"CRAWLER\",VR=1.5,WT=\"OFF\",DS=\"ON\"\r\n");
  const RecordConfig own = parse(nucleus + "    water_track: true\n");
  EXPECT_EQ(drivers::bottom_track_command(*own.dvl->nucleus_command.bottom_track),
            "SETBT,WT=\"ON\",DS=\"ON\"\r\n");
  const std::string mode = testing::error_message([&] { parse(nucleus + "    mode: slow\n"); });
  EXPECT_NE(mode.find("dvl.bottom_track.mode"), std::string::npos) << mode;
  EXPECT_NE(mode.find("'SLOW' is not a bottom-track mode; use FAST_ACQ, AUTO or CRAWLER"),
            std::string::npos)
      << mode;
  EXPECT_NE(testing::error_message([&] {
              parse(nucleus + "    velocity_range_mps: 40\n");
            }).find("dvl.bottom_track.velocity_range_mps"),
            std::string::npos);
  EXPECT_NE(testing::error_message([&] { parse(nucleus + "    range: 3\n"); }).find("range"),
            std::string::npos);
  const std::string not_started = testing::error_message([&] {
    parse(std::string(kMinimal) +
          "dvl:\n  kind: nucleus\n  calibration: calib/dvl0.yaml\n  bottom_track:\n    "
          "mode: AUTO\n");
  });
  EXPECT_NE(not_started.find("dvl.bottom_track"), std::string::npos) << not_started;
  EXPECT_NE(not_started.find("start: true"), std::string::npos) << not_started;
}

TEST_F(RecordConfigTest, MistakesNameTheFileAndKey) {
  EXPECT_NE(testing::error_message([&] {
              parse(std::string(kMinimal) + "dvl:\n  kind: a50\n");
            }).find("'a50' is not a DVL kind; use waterlinked or nucleus"),
            std::string::npos);
  EXPECT_NE(testing::error_message([&] {
              parse(std::string(kMinimal) + "mavlink:\n  endpoint: serial:/dev/x\n");
            }).find("mavlink.endpoint"),
            std::string::npos);
  EXPECT_NE(testing::error_message([&] {
              parse(std::string(kMinimal) + "  latency_s: -1\n");
            }).find("camera.latency_s"),
            std::string::npos);
  EXPECT_NE(testing::error_message([&] {
              parse(std::string(kMinimal) + "  exposure: 3\n");
            }).find("exposure"),
            std::string::npos);
  const std::string missing = testing::error_message([&] {
    parse("scene: calib/scene.yaml\ncamera:\n  uri: v4l2:0\n  calibration: calib/nope.yaml\n");
  });
  EXPECT_NE(missing.find("camera.calibration"), std::string::npos) << missing;
  EXPECT_NE(missing.find("nope.yaml"), std::string::npos) << missing;
  EXPECT_NE(testing::error_message([&] { parse("camera:\n  uri: v4l2:0\n"); }).find("scene"),
            std::string::npos);
  EXPECT_NE(testing::error_message([&] {
              parse(std::string(kMinimal) +
                    "dvl:\n  kind: waterlinked\n  start: true\n  calibration: calib/dvl0.yaml\n");
            }).find("dvl.start"),
            std::string::npos);
}

TEST(RecordConfigDoc, EveryKeyHasARow) {
  const std::string rows = record_config_param_rows();
  for (const char* key :
       {"`scene`", "`camera.uri`", "`camera.latency_s`", "`dvl.kind`", "`dvl.port`", "`dvl.start`",
        "`dvl.password`", "`dvl.tcp.idle_timeout_s`", "`dvl.serial.baud`", "`dvl.clock.window_s`",
        "`dvl.bottom_track.mode`", "`dvl.bottom_track.velocity_range_mps`",
        "`dvl.bottom_track.water_track`", "`mavlink.endpoint`",
        "`mavlink.water_depth.pressure_source`", "`mavlink.clock.max_jump_s`"}) {
    EXPECT_NE(rows.find(key), std::string::npos) << key;
  }
}

}  // namespace
}  // namespace pensight::live
