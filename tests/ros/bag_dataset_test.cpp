// A rendered dataset written as a ROS 1 bag (dataset_to_bag.h) and converted back with
// bag_to_dataset comes back exact: the same frame files, DVL samples, depths and attitudes (to
// 1e-9) and camera, and `pensight run`'s pipeline gives the same estimates on both.
#include <gtest/gtest.h>

#include <unistd.h>
#include "pipeline/dataset/sensor_mounts.h"

#include <cmath>
#include <filesystem>
#include <string>

#include "core/file_bytes.h"
#include "core/units.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/estimates_csv.h"
#include "ros/bag_dataset.h"
#include "sim/generate.h"
#include "sim/scenario.h"
#include "tests/ros/dataset_to_bag.h"
#include "tests/support/rendered_run.h"
#include "tests/support/test_seed.h"
#include "tests/support/vulkan_fixture.h"
#include "tools/runner.h"

namespace pensight {
namespace {
namespace fs = std::filesystem;

// NaN matches NaN: an invalid DVL sample and a missing beam range stay so.
void expect_same(double a, double b, const std::string& what) {
  EXPECT_TRUE((std::isnan(a) && std::isnan(b)) || a == b) << what << ": " << a << " vs " << b;
}

class BagRoundTrip : public ::testing::Test {
 protected:
  // follow.yaml for 1.5 s (16 frames, DVL dropouts and all), rendered once for the suite with a
  // fresh seed for its sensor noise.
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("pensight_bag_dataset_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    sim::Scenario s = testing::shipped_scenario("follow.yaml", 1.5);
    s.seed = testing::fresh_seed();
    sim::generate_dataset(s, *testing::test_renderer(s), *dir_ / "original");
    original_ = new Dataset(read_dataset(*dir_ / "original"));
  }
  static void TearDownTestSuite() {
    delete original_;
    fs::remove_all(*dir_);
    delete dir_;
  }

  static fs::path dir() { return *dir_; }
  static const Dataset& original() { return *original_; }

  // The bag of the original dataset (written once per name).
  static fs::path bag(const std::string& name, const testing::BagWriteOptions& o = {}) {
    const fs::path file = dir() / (name + ".bag");
    if (!fs::exists(file)) testing::dataset_to_bag(original(), file, o);
    return file;
  }

  // `bag_file` converted into dir()/name, with the original's scene and, when `mounts`, its
  // camera and DVL files.
  static Dataset convert(const fs::path& bag_file, const std::string& name, bool mounts) {
    BagConversionOptions o;
    o.scene_file = original().root / "scene.yaml";
    if (mounts) {
      o.camera_file = original().root / "cam0" / "sensor.yaml";
      o.dvl_file = original().root / "dvl0" / "sensor.yaml";
    }
    const BagConversionSummary s = bag_to_dataset(bag_file, dir() / name, o);
    EXPECT_TRUE(s.skipped.empty());
    EXPECT_EQ(s.frames, original().frames.size());
    return read_dataset(dir() / name);
  }

 private:
  static fs::path* dir_;
  static Dataset* original_;
};

fs::path* BagRoundTrip::dir_ = nullptr;
Dataset* BagRoundTrip::original_ = nullptr;

TEST_F(BagRoundTrip, EveryFrameAndSensorSampleComesBack) {
  const Dataset& a = original();
  ASSERT_TRUE(a.dvl0 && a.dvl0->has_beam_ranges && a.pressure0 && a.imu0);
  const Dataset b = convert(bag("mono8"), "mono8", true);

  ASSERT_EQ(b.frames.size(), a.frames.size());
  for (size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(b.frames[i].timestamp_ns, a.frames[i].timestamp_ns);
    EXPECT_EQ(read_file_bytes(b.root / "cam0" / "data" / b.frames[i].filename),
              read_file_bytes(a.root / "cam0" / "data" / a.frames[i].filename))
        << "frame " << i;
  }
  EXPECT_EQ(camera_yaml(b.cam0), camera_yaml(a.cam0));

  ASSERT_TRUE(b.dvl0 && b.dvl0->has_beam_ranges);
  EXPECT_EQ(dvl_yaml(b.dvl0->calibration), dvl_yaml(a.dvl0->calibration));
  ASSERT_EQ(b.dvl0->samples.size(), a.dvl0->samples.size());
  for (size_t i = 0; i < a.dvl0->samples.size(); ++i) {
    const DvlSample &sa = a.dvl0->samples[i], &sb = b.dvl0->samples[i];
    const std::string at = "DVL sample " + std::to_string(i);
    EXPECT_EQ(sb.timestamp_ns, sa.timestamp_ns) << at;
    EXPECT_EQ(sb.valid, sa.valid) << at;
    for (int k = 0; k < 3; ++k) expect_same(sb.velocity_B_mps[k], sa.velocity_B_mps[k], at);
    for (size_t k = 0; k < 4; ++k) expect_same(sb.beam_range_m[k], sa.beam_range_m[k], at);
  }

  ASSERT_TRUE(b.pressure0);
  ASSERT_EQ(b.pressure0->size(), a.pressure0->size());
  for (size_t i = 0; i < a.pressure0->size(); ++i) {
    EXPECT_EQ((*b.pressure0)[i].timestamp_ns, (*a.pressure0)[i].timestamp_ns);
    EXPECT_NEAR((*b.pressure0)[i].depth_m, (*a.pressure0)[i].depth_m, 1e-9) << "pressure " << i;
  }

  ASSERT_TRUE(b.imu0);
  ASSERT_EQ(b.imu0->size(), a.imu0->size());
  for (size_t i = 0; i < a.imu0->size(); ++i) {
    const AttitudeSample &sa = (*a.imu0)[i], &sb = (*b.imu0)[i];
    EXPECT_EQ(sb.timestamp_ns, sa.timestamp_ns);
    EXPECT_NEAR(sb.roll_rad, sa.roll_rad, 1e-9) << "attitude " << i;
    EXPECT_NEAR(sb.pitch_rad, sa.pitch_rad, 1e-9) << "attitude " << i;
    EXPECT_NEAR(wrap_angle(sb.yaw_rad - sa.yaw_rad), 0, 1e-9) << "attitude " << i;
  }
  EXPECT_FALSE(b.groundtruth0);  // a bag has no truth
}

TEST_F(BagRoundTrip, CameraInfoGivesTheIntrinsicsAndAForwardMountAtTheOrigin) {
  const Dataset b = convert(bag("mono8"), "camera_info", false);
  const PinholeCamera &ka = original().cam0.camera, &kb = b.cam0.camera;
  EXPECT_EQ(kb.width_px, ka.width_px);
  EXPECT_EQ(kb.height_px, ka.height_px);
  for (const auto& [x, y] : {std::pair{kb.fx_px, ka.fx_px},
                             {kb.fy_px, ka.fy_px},
                             {kb.cx_px, ka.cx_px},
                             {kb.cy_px, ka.cy_px},
                             {kb.k1, ka.k1},
                             {kb.k2, ka.k2},
                             {kb.p1, ka.p1},
                             {kb.p2, ka.p2}}) {
    EXPECT_EQ(x, y);
  }
  EXPECT_EQ(b.cam0.rate_hz, original().cam0.rate_hz);  // from the frames' bag times
  EXPECT_TRUE(b.cam0.T_body_camera.isApprox(forward_mount(Eigen::Vector3d::Zero(), 0, 0)));
  // The default DVL: at the body origin, forward, four unit beams 25 deg off its axis.
  ASSERT_TRUE(b.dvl0);
  EXPECT_TRUE(b.dvl0->calibration.T_body_dvl.translation().isZero());
  EXPECT_EQ(b.dvl0->calibration.rate_hz, original().dvl0->calibration.rate_hz);
  for (const Eigen::Vector3d& beam : b.dvl0->calibration.beam_directions_S) {
    EXPECT_NEAR(std::acos(beam.normalized().z()), deg_to_rad(25), 1e-3);
  }
}

TEST_F(BagRoundTrip, ColourAndCompressedImagesGiveTheSameFrames) {
  for (const std::string encoding : {"bgr8", "rgb8", "png"}) {
    testing::BagWriteOptions o;
    o.image_encoding = encoding;
    const Dataset b = convert(bag(encoding, o), encoding, true);
    ASSERT_EQ(b.frames.size(), original().frames.size()) << encoding;
    for (size_t i = 0; i < b.frames.size(); ++i) {
      EXPECT_EQ(b.load_frame(i).pixels, original().load_frame(i).pixels) << encoding << " " << i;
    }
  }
}

TEST_F(BagRoundTrip, RunGivesTheSameEstimatesAsTheDataset) {
  const Dataset b = convert(bag("mono8"), "for_run", true);
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  options.write_published_global_pose = false;
  run_dataset(original(), dir() / "run_original", options, testing::test_device());
  run_dataset(b, dir() / "run_bag", options, testing::test_device());
  const auto ra = read_estimates_csv(dir() / "run_original" / "estimates.csv");
  const auto rb = read_estimates_csv(dir() / "run_bag" / "estimates.csv");
  ASSERT_EQ(rb.size(), ra.size());
  size_t with_pose = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    const EstimateRow &x = ra[i], &y = rb[i];
    EXPECT_EQ(y.timestamp_ns, x.timestamp_ns);
    EXPECT_EQ(y.valid_rois, x.valid_rois) << "row " << i;
    const std::pair<double, double> values[] = {{x.d_net_fft_m, y.d_net_fft_m},
                                                {x.psi_net_fft_rad, y.psi_net_fft_rad},
                                                {x.pitch_net_fft_rad, y.pitch_net_fft_rad},
                                                {x.r_g_m, y.r_g_m},
                                                {x.rho_g_rad, y.rho_g_rad},
                                                {x.z_g_m, y.z_g_m},
                                                {x.psi_g_rad, y.psi_g_rad}};
    for (const auto& [va, vb] : values) {
      EXPECT_EQ(std::isnan(va), std::isnan(vb)) << "row " << i;
      if (!std::isnan(va)) {
        EXPECT_NEAR(vb, va, 1e-9) << "row " << i;
      }
    }
    with_pose += !std::isnan(x.d_net_fft_m);
  }
  EXPECT_GT(with_pose, ra.size() / 2);  // the comparison is of real estimates
}

}  // namespace
}  // namespace pensight
