// The live camera against the camera stand-in (a YUV4MPEG2 stream on TCP, read by OpenCV's FFmpeg
// back-end): frames arrive exactly, a stream that stops for 3 s is reopened, a camera that never
// answers and frames of the wrong size are counted and said, never thrown.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <random>
#include <thread>

#include "live/camera_source.h"
#include "live/device_standins.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"

namespace pensight::live {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 48, kHeight = 36;

class CameraSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pensight_camera_source_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `frames` random frames at 10 Hz.
  Dataset make_dataset(int frames) {
    DatasetContents c;
    c.cam0.camera.width_px = kWidth;
    c.cam0.camera.height_px = kHeight;
    c.dvl0.reset();
    c.pressure0 = c.imu0 = c.groundtruth0 = false;
    DatasetWriter w(dir_ / "ds", c);
    std::mt19937 rng(static_cast<unsigned>(::getpid()));
    for (int i = 0; i < frames; ++i) {
      ImageU8 image(kWidth, kHeight);
      for (uint8_t& p : image.pixels) p = static_cast<uint8_t>(rng());
      w.add_frame(1'000'000'000 + int64_t{i} * 100'000'000, image);
    }
    w.finish();
    return read_dataset(dir_ / "ds");
  }

  // A config whose camera is the stand-in's stream on an ephemeral port.
  static RecordConfig camera_only(const Dataset& d) {
    RecordConfig c;
    c.scene = d.scene;
    c.camera.uri = parse_camera_uri("tcp://127.0.0.1:0");
    c.camera.calibration = d.cam0;
    return c;
  }

  fs::path dir_;
};

CameraUri stream_of(const DeviceStandIns& s) {
  return parse_camera_uri("tcp://127.0.0.1:" + std::to_string(s.ports().camera));
}

TEST_F(CameraSourceTest, TheStandInsFramesArriveExactlyAndInOrder) {
  const Dataset d = make_dataset(20);
  DeviceStandIns standins(d, camera_only(d));
  std::atomic<bool> stop{false}, done{false};
  std::thread serve([&] {
    standins.run(stop);
    done = true;
  });
  CameraSource camera(stream_of(standins), d.cam0.camera);
  std::vector<CameraFrame> frames;
  while (!done) {
    if (auto f = camera.take(0.1)) frames.push_back(std::move(*f));
  }
  serve.join();
  // Every frame arrives exactly, in order; one the consumer had not taken yet when the next came
  // (the stream's first two arrive together after FFmpeg's probe) is dropped, not queued.
  const CameraCounters c = camera.counters();
  EXPECT_EQ(c.frames, d.frames.size()) << camera.last_error();
  EXPECT_EQ(frames.size() + c.dropped, d.frames.size());
  EXPECT_LE(c.dropped, 2u);
  size_t next = 0, previous = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    while (next < d.frames.size() && d.load_frame(next).pixels != frames[k].image.pixels) ++next;
    ASSERT_LT(next, d.frames.size()) << "frame " << k << " is none of the served ones, in order";
    if (k >= 2) {
      // Stamped on arrival: 100 ms per frame apart within the loopback's jitter, once past the
      // first two (read together when the stream opens).
      EXPECT_NEAR(static_cast<double>(frames[k].timestamp_ns - frames[k - 1].timestamp_ns) / 1e6,
                  100.0 * static_cast<double>(next - previous), 40)
          << k;
    }
    previous = next;
  }
}
TEST_F(CameraSourceTest, AStreamThatStopsForThreeSecondsIsReopened) {
  const Dataset d = make_dataset(60);
  StandInParams p;
  p.camera_pause_at_s = 1.0;
  p.camera_pause_s = 3.0;
  DeviceStandIns standins(d, camera_only(d), p);
  std::atomic<bool> stop{false}, done{false};
  std::thread serve([&] {
    standins.run(stop);
    done = true;
  });
  CameraSource camera(stream_of(standins), d.cam0.camera);
  size_t before = 0, after = 0;
  while (!done) {
    if (camera.take(0.2)) (camera.counters().stalls == 0 ? before : after) += 1;
  }
  serve.join();
  const CameraCounters c = camera.counters();
  EXPECT_GE(c.stalls, 1u);
  EXPECT_GE(c.reconnects, 1u);
  EXPECT_GE(before, 8u);
  EXPECT_GE(after, 5u) << camera.last_error();
  EXPECT_NE(camera.last_error().find("no frame within 2 s"), std::string::npos)
      << camera.last_error();
}

TEST_F(CameraSourceTest, ACameraThatNeverAnswersIsCountedNotThrown) {
  CameraSourceParams p;
  p.timeout_s = 0.3;
  p.reconnect_s = 0.1;
  PinholeCamera cam;
  CameraSource camera(parse_camera_uri("tcp://127.0.0.1:9"), cam, p);
  EXPECT_FALSE(camera.take(0.8));
  EXPECT_GE(camera.counters().open_failures, 2u);
  EXPECT_NE(camera.last_error().find("did not open; retrying every 0.1 s"), std::string::npos)
      << camera.last_error();
}

TEST_F(CameraSourceTest, FramesOfTheWrongSizeAreSkippedAndSaid) {
  const Dataset d = make_dataset(8);
  DeviceStandIns standins(d, camera_only(d));
  std::atomic<bool> stop{false};
  std::thread serve([&] { standins.run(stop); });
  PinholeCamera other = d.cam0.camera;
  other.width_px = 64;
  CameraSource camera(stream_of(standins), other);
  EXPECT_FALSE(camera.take(2.5));
  serve.join();
  EXPECT_GE(camera.counters().wrong_size, 5u);
  EXPECT_NE(camera.last_error().find("frame of 48x36 px, the calibration's is 64x36"),
            std::string::npos)
      << camera.last_error();
}

TEST_F(CameraSourceTest, TheStandInsNameACameraAddressTheyCannotServe) {
  const Dataset d = make_dataset(1);
  RecordConfig c = camera_only(d);
  for (const char* uri : {"tcp://127.0.0.1:x", "tcp://127.0.0.1", "tcp://127.0.0.1:70000"}) {
    c.camera.uri = parse_camera_uri(uri);
    try {
      DeviceStandIns standins(d, c);
      ADD_FAILURE() << uri << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("no port 0-65535 after the host"), std::string::npos)
          << e.what();
    }
  }
  c.camera.uri = parse_camera_uri("v4l2:/dev/video0");
  EXPECT_THROW(DeviceStandIns(d, c), Error);
}

// A dataset played at its own pace to a consumer that takes every third frame: the others are
// dropped, never queued.
TEST_F(CameraSourceTest, ASlowConsumerGetsTheNewestFrameAndDropsAreCounted) {
  const Dataset d = make_dataset(15);
  CameraSource camera(parse_camera_uri("dataset:" + (dir_ / "ds").string()), d.cam0.camera);
  size_t taken = 0;
  while (!camera.finished()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(290));
    if (camera.take(0)) ++taken;
  }
  const CameraCounters c = camera.counters();
  EXPECT_EQ(c.frames, 15u);
  EXPECT_EQ(c.taken, taken);
  EXPECT_EQ(c.taken + c.dropped, 15u);
  EXPECT_GE(c.dropped, 8u);
  EXPECT_THROW(CameraSource(parse_camera_uri("dataset:" + (dir_ / "none").string()), d.cam0.camera),
               Error);
}

}  // namespace
}  // namespace pensight::live
