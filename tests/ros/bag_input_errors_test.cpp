// Bags that bag_to_dataset must refuse with a clear error (and no output), sensor glitches it
// skips and counts, the --topics file, and the REP 103 frame conversions.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <string>

#include "core/error.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/dataset_reader.h"
#include "ros/bag_dataset.h"
#include "ros/ros_frames.h"
#include "ros/ros_messages_detail.h"
#include "tests/support/test_seed.h"

namespace pensight {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 8, kHeight = 6;
constexpr int64_t kSecond_ns = 1'000'000'000;

ros::Time stamp(int64_t t_ns) {
  ros::Time t;
  t.fromNSec(static_cast<uint64_t>(t_ns));
  return t;
}

// A frame stamped t_ns, recorded at bag time t_ns unless bag_time_ns says otherwise.
void write_frame(rosbag::Bag& bag, int64_t t_ns, const std::string& encoding = "mono8",
                 int64_t bag_time_ns = 0) {
  msg::Image m;
  m.header.stamp = stamp(t_ns);
  m.width = kWidth;
  m.height = kHeight;
  m.encoding.assign(encoding.begin(), encoding.end());
  m.step = 2 * kWidth;  // room for mono16
  m.data.assign(m.step * kHeight, static_cast<uint8_t>(t_ns / 1'000'000));
  bag.write("/camera/image_raw", bag_time_ns ? stamp(bag_time_ns) : m.header.stamp, m);
}

void write_camera_info(rosbag::Bag& bag) {
  msg::CameraInfo m;
  m.header.stamp = stamp(kSecond_ns);
  m.width = kWidth;
  m.height = kHeight;
  m.K = {10, 0, 3.5, 0, 10, 2.5, 0, 0, 1};
  bag.write("/camera/camera_info", m.header.stamp, m);
}

void write_pressure(rosbag::Bag& bag, int64_t t_ns, double pressure_pa,
                    const std::string& topic = "/pressure") {
  msg::FluidPressure m;
  m.header.stamp = stamp(t_ns);
  m.fluid_pressure = pressure_pa;
  bag.write(topic, stamp(t_ns), m);
}

class BagInputErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pensight_bag_input_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "scene.yaml") << scene_yaml(SceneConfig{});
    options_.scene_file = dir_ / "scene.yaml";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A bag of three frames and a camera_info, plus what `extra` writes.
  fs::path bag(const std::function<void(rosbag::Bag&)>& extra = {}) {
    const fs::path file = dir_ / "in.bag";
    rosbag::Bag b(file.string(), rosbag::bagmode::Write);
    write_camera_info(b);
    for (int i = 0; i < 3; ++i) write_frame(b, kSecond_ns + i * kSecond_ns / 10);
    if (extra) extra(b);
    return file;
  }

  BagConversionSummary convert(const fs::path& bag_file) {
    return bag_to_dataset(bag_file, dir_ / "out", options_);
  }

  // Converting `bag_file` fails with a message containing every one of `parts`, and leaves
  // nothing beside the inputs.
  void expect_error(const fs::path& bag_file, const std::vector<std::string>& parts) {
    try {
      convert(bag_file);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      for (const std::string& p : parts)
        EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "scene.yaml" || name.ends_with(".bag") || name.ends_with(".yaml"))
          << "left behind: " << name;
    }
  }

  fs::path dir_;
  BagConversionOptions options_;
};

TEST_F(BagInputErrors, ASmallBagConverts) {
  const BagConversionSummary s = convert(bag());
  EXPECT_EQ(s.frames, 3u);
  const Dataset d = read_dataset(dir_ / "out");
  EXPECT_EQ(d.frames.size(), 3u);
  EXPECT_EQ(d.cam0.camera.fx_px, 10);
  EXPECT_EQ(d.cam0.rate_hz, 10);
  EXPECT_FALSE(d.dvl0 || d.pressure0 || d.imu0);  // absent topics are absent sensors
}

TEST_F(BagInputErrors, AnUnsupportedEncodingIsNamedWithTheSupportedOnes) {
  expect_error(bag([](rosbag::Bag& b) { write_frame(b, 2 * kSecond_ns, "mono16"); }),
               {"/camera/image_raw", "'mono16'", "mono8, bgr8, rgb8"});
}

TEST_F(BagInputErrors, NoCameraInfoWithoutCameraIsAnError) {
  const fs::path file = dir_ / "no_info.bag";
  {
    rosbag::Bag b(file.string(), rosbag::bagmode::Write);
    write_frame(b, kSecond_ns);
  }
  expect_error(file, {"/camera/camera_info", "--camera"});
  // With --camera the same bag converts.
  CameraCalibration cam;
  cam.camera.width_px = kWidth;
  cam.camera.height_px = kHeight;
  std::ofstream(dir_ / "sensor.yaml") << camera_yaml(cam);
  options_.camera_file = dir_ / "sensor.yaml";
  EXPECT_EQ(convert(file).frames, 1u);
}

TEST_F(BagInputErrors, NoSceneNamesTheOption) {
  options_.scene_file.clear();
  expect_error(bag(), {"--scene"});
}

TEST_F(BagInputErrors, AMissingBagOrAnotherFileIsAnError) {
  expect_error(dir_ / "missing.bag", {"missing.bag", "not found"});
  std::ofstream(dir_ / "text.bag") << "#ROSBAG V2.0\nnot really\n";
  expect_error(dir_ / "text.bag", {"text.bag", "ROS 1 bag"});
  std::ofstream(dir_ / "csv.bag") << "#timestamp [ns],depth [m]\n1,2\n";
  expect_error(dir_ / "csv.bag", {"csv.bag", "ROS 1 bag"});
  const fs::path cut = bag();  // a recording cut short: its index at the end is missing
  fs::resize_file(cut, fs::file_size(cut) / 2);
  expect_error(cut, {"in.bag", "rosbag reindex"});
}

// Overwrites the `bytes` bytes after the first `marker` in `file` with `value` (little endian).
void patch_after(const fs::path& file, const std::string& marker, uint64_t value, int bytes) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t at = data.find(marker);
  ASSERT_NE(at, std::string::npos) << marker;
  f.seekp(static_cast<std::streamoff>(at + marker.size()));
  for (int i = 0; i < bytes; ++i) f.put(static_cast<char>((value >> (8 * i)) & 0xff));
}

void patch_field(const fs::path& file, const std::string& field, uint64_t value, int bytes) {
  patch_after(file, field + "=", value, bytes);
}

// rosbag believes the lengths in a file (it would allocate gigabytes for a damaged one), so the
// record structure is checked first (ros/bag_structure.h); each damage is named with its offset.
TEST_F(BagInputErrors, DamagedLengthsAreNamedWithTheirOffset) {
  fs::path file = bag();
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(13);  // the bag header record's header length, after the magic line
    for (int i = 0; i < 4; ++i) f.put(static_cast<char>(i < 3 ? 0xff : 0x7f));
  }
  expect_error(file, {"in.bag", "not a readable ROS 1 bag", "byte 13", "runs past the end"});
  file = bag();
  patch_field(file, "index_pos", fs::file_size(file) + 100, 8);
  expect_error(file, {"in.bag", "index position", "outside the file"});
  // rosbag reads the connection and chunk-info records from the index position on, as many as
  // the bag header counts: another position or count would have it read other bytes as lengths.
  file = bag();
  patch_field(file, "index_pos", 14, 8);
  expect_error(file, {"in.bag", "index position 14 is not the start of a record"});
  file = bag();
  patch_field(file, "conn_count", 9, 4);
  expect_error(file, {"in.bag", "lacks the bag header's 9 connection records"});
  file = bag();
  patch_field(file, "size", 0xfffffff0u, 4);  // the chunk's
  expect_error(file, {"in.bag", "uncompressed chunk", "says it has 4294967280"});
  // Compressed chunks are unpacked to check their records; a size field beyond the limit is
  // refused before any allocation.
  for (const auto& [name, compression] :
       {std::pair{"lz4", rosbag::compression::LZ4}, {"bz2", rosbag::compression::BZ2}}) {
    file = dir_ / (std::string(name) + ".bag");
    {
      rosbag::Bag b(file.string(), rosbag::bagmode::Write);
      b.setCompression(compression);
      write_camera_info(b);
      write_frame(b, kSecond_ns);
    }
    EXPECT_EQ(convert(file).frames, 1u) << name;
    fs::remove_all(dir_ / "out");
    patch_field(file, "size", 0xfffffff0u, 4);
    expect_error(file, {std::string(name) + ".bag", "unpacks to 4294967280 bytes"});
  }
}

// A message whose array length field says more elements than the message has bytes: the
// deserializer would allocate them (here 4 G doubles) before it finds the message short.
TEST_F(BagInputErrors, AnArrayLongerThanItsMessageIsDamage) {
  const fs::path file = dir_ / "in.bag";
  {
    rosbag::Bag b(file.string(), rosbag::bagmode::Write);
    msg::CameraInfo m;
    m.header.stamp = stamp(kSecond_ns);
    m.width = kWidth;
    m.height = kHeight;
    m.distortion_model = "plumb_bob_then_d";  // D's length follows this string
    m.D = {0, 0, 0, 0, 0};
    m.K = {10, 0, 3.5, 0, 10, 2.5, 0, 0, 1};
    b.write("/camera/camera_info", m.header.stamp, m);
    for (int i = 0; i < 3; ++i) write_frame(b, kSecond_ns + i * kSecond_ns / 10);
  }
  EXPECT_EQ(convert(file).frames, 3u);
  fs::remove_all(dir_ / "out");
  patch_after(file, "plumb_bob_then_d", 0xfffffff0u, 4);
  expect_error(file, {"in.bag", "damaged", "an array of 4294967280 elements", "bytes can be"});
  try {  // bounded by the message's own size, not by kMaxMessageArrayBytes
    convert(file);
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find(std::to_string(msg::kMaxMessageArrayBytes)),
              std::string::npos)
        << e.what();
  }
}

// Outside the bag reader (roscpp deserializing the node's subscriptions) the bound is
// kMaxMessageArrayBytes: a damaged length is an exception roscpp reports, not 2 GB zeroed.
TEST(RosMessages, AnArrayBeyondTheBoundIsAStreamError) {
  msg::CameraInfo m;
  m.distortion_model = "plumb_bob_then_d";
  m.D = {0, 0, 0, 0, 0};
  std::vector<uint8_t> buffer(ros::serialization::serializationLength(m));
  ros::serialization::OStream out(buffer.data(), static_cast<uint32_t>(buffer.size()));
  ros::serialization::serialize(out, m);
  const std::string bytes(buffer.begin(), buffer.end());
  const size_t at = bytes.find("plumb_bob_then_d") + 16;
  const uint32_t doubles = (msg::kMaxMessageArrayBytes / 8) + 1;
  for (int i = 0; i < 4; ++i) buffer[at + i] = static_cast<uint8_t>(doubles >> (8 * i));
  msg::CameraInfo read;
  ros::serialization::IStream in(buffer.data(), static_cast<uint32_t>(buffer.size()));
  EXPECT_THROW(ros::serialization::deserialize(in, read),
               ros::serialization::StreamOverrunException);
}

TEST_F(BagInputErrors, AnEmptyBagIsAnError) {
  const fs::path file = dir_ / "empty.bag";
  rosbag::Bag(file.string(), rosbag::bagmode::Write).close();
  expect_error(file, {"empty.bag", "no messages"});
}

TEST_F(BagInputErrors, ABagWithoutCameraImagesListsItsTopics) {
  const fs::path file = dir_ / "no_images.bag";
  {
    rosbag::Bag b(file.string(), rosbag::bagmode::Write);
    write_pressure(b, kSecond_ns, 2e5);
  }
  expect_error(
      file, {"/camera/image_raw", "/pressure (sensor_msgs/FluidPressure, 1 messages)", "--topics"});
}

TEST_F(BagInputErrors, ATopicOfTheWrongTypeNamesTheRole) {
  expect_error(bag([](rosbag::Bag& b) {
                 msg::Float64MultiArray m;
                 m.data = {1.0};
                 b.write("/pressure", stamp(kSecond_ns), m);
               }),
               {"'/pressure'", "std_msgs/Float64MultiArray", "'pressure'",
                "sensor_msgs/FluidPressure", "--topics"});
}

TEST_F(BagInputErrors, CameraFramesOutOfOrderAreAnError) {
  // Recorded last, stamped before the first.
  expect_error(bag([](rosbag::Bag& b) { write_frame(b, kSecond_ns / 2, "mono8", 2 * kSecond_ns); }),
               {"/camera/image_raw", "frame 4", "time order"});
}

TEST_F(BagInputErrors, AFrameOfAnotherSizeIsAnError) {
  expect_error(bag([](rosbag::Bag& b) {
                 msg::Image m;
                 m.header.stamp = stamp(3 * kSecond_ns);
                 m.width = m.step = 4;
                 m.height = 2;
                 m.encoding = "mono8";
                 m.data.assign(8, 0);
                 b.write("/camera/image_raw", m.header.stamp, m);
               }),
               {"/camera/image_raw", "4x2", "8x6"});
}

TEST_F(BagInputErrors, SensorGlitchesAreSkippedAndCounted) {
  const WaterColumn water;
  const BagConversionSummary s = convert(bag([&](rosbag::Bag& b) {
    for (int i = 0; i < 10; ++i) {
      const double p = i == 3 ? kNaN : pressure_from_depth_pa(1.0 + 0.1 * i, water);
      write_pressure(b, kSecond_ns + (i == 6 ? 5 : i) * kSecond_ns / 10, p);  // 6 repeats 5
    }
    msg::Imu imu;  // a zero quaternion, then a level one
    imu.header.stamp = stamp(kSecond_ns);
    b.write("/imu/data", imu.header.stamp, imu);
    imu.header.stamp = stamp(2 * kSecond_ns);
    imu.orientation.w = 1;
    b.write("/imu/data", imu.header.stamp, imu);
    imu.header.stamp = stamp(3 * kSecond_ns);
    imu.orientation_covariance[0] = -1;  // "no orientation"
    b.write("/imu/data", imu.header.stamp, imu);
    imu.header.stamp = stamp(4 * kSecond_ns);
    imu.orientation_covariance[0] = 0;
    b.write("/imu/data", imu.header.stamp, imu);
  }));
  ASSERT_EQ(s.skipped.size(), 2u);
  EXPECT_EQ(s.skipped[0].topic, "/pressure");
  EXPECT_EQ(s.skipped[0].skipped, 2u);
  EXPECT_EQ(s.skipped[0].messages, 10u);
  EXPECT_EQ(s.skipped[1].topic, "/imu/data");
  EXPECT_EQ(s.skipped[1].skipped, 2u);
  const Dataset d = read_dataset(dir_ / "out");
  ASSERT_TRUE(d.pressure0 && d.imu0);
  ASSERT_EQ(d.pressure0->size(), 8u);
  EXPECT_NEAR(d.pressure0->back().depth_m, 1.9, 1e-9);
  EXPECT_EQ(d.imu0->size(), 2u);
}

TEST_F(BagInputErrors, ASensorTopicOfMostlyBadMessagesFails) {
  expect_error(bag([](rosbag::Bag& b) {
                 for (int i = 0; i < 4; ++i) write_pressure(b, kSecond_ns + i, i == 0 ? 2e5 : kNaN);
               }),
               {"'/pressure'", "not finite", "3 of 4 messages"});
}

TEST_F(BagInputErrors, ATopicsFileRemapsRolesAndRefusesATypo) {
  std::ofstream(dir_ / "topics.yaml") << "pressure: /bar30/pressure\n";
  options_.topics = read_bag_topics(dir_ / "topics.yaml");
  EXPECT_EQ(options_.topics.image, BagTopics{}.image);
  convert(bag([](rosbag::Bag& b) { write_pressure(b, kSecond_ns, 2e5, "/bar30/pressure"); }));
  const Dataset d = read_dataset(dir_ / "out");
  ASSERT_TRUE(d.pressure0);
  EXPECT_EQ(d.pressure0->size(), 1u);

  std::ofstream(dir_ / "typo.yaml") << "image: /cam\npresure: /bar30/pressure\n";
  try {
    read_bag_topics(dir_ / "typo.yaml");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("typo.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'presure'"), std::string::npos) << e.what();
  }
}

TEST_F(BagInputErrors, BadOptionsNameTheOption) {
  options_.water.density_kg_m3 = 0;
  expect_error(bag(), {"--water-density"});
}

// REP 103 (ENU world, FLU body) against P (z down, taken as NED) and FRD.
TEST(RosFrames, HeadingRollAndPitchHaveTheContractsSigns) {
  const auto rpy = [](const Eigen::Quaterniond& q_enu_flu) {
    return rpy_from_rotation(rotation_pen_body_from_ros(q_enu_flu));
  };
  const auto about = [](double a, const Eigen::Vector3d& axis) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(a, axis));
  };
  const double quarter = std::numbers::pi / 2;
  // Level and facing east (ROS yaw 0): yaw +90 deg in P (clockwise from north seen from above).
  EXPECT_TRUE(rpy(Eigen::Quaterniond::Identity()).isApprox(Eigen::Vector3d(0, 0, quarter)));
  // Facing north (ROS yaw +90 deg): yaw 0.
  const Eigen::Quaterniond north = about(quarter, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(rpy(north).isZero(1e-12));
  // ROS roll +0.1 about x forward lifts the left side: right side down, FRD roll +0.1.
  EXPECT_TRUE(rpy(north * about(0.1, Eigen::Vector3d::UnitX()))
                  .isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-12));
  // ROS pitch +0.1 about y left is nose down: FRD pitch (nose up positive) -0.1.
  EXPECT_TRUE((rpy(north * about(0.1, Eigen::Vector3d::UnitY())) - Eigen::Vector3d(0, -0.1, 0))
                  .isZero(1e-12));
}

TEST(RosFrames, AttitudesRoundTrip) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> angle(-3, 3), tilt(-1.5, 1.5);
  for (int i = 0; i < 1000; ++i) {
    const double roll = angle(rng), pitch = tilt(rng), yaw = angle(rng);
    const Eigen::Vector3d back = rpy_from_rotation(rotation_pen_body_from_ros(
        ros_orientation_from_pen_body(rotation_from_rpy(roll, pitch, yaw))));
    EXPECT_NEAR(back.x(), roll, 1e-9);
    EXPECT_NEAR(back.y(), pitch, 1e-9);
    EXPECT_NEAR(back.z(), yaw, 1e-9);
  }
}

}  // namespace
}  // namespace pensight
