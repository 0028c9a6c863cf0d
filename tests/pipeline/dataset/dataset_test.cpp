// Dataset contract I/O: round trips through DatasetWriter/read_dataset, EstimatesCsvWriter and
// TrajectoryTumWriter, and the refusals for malformed input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/csv.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"
#include "core/units.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "pipeline/dataset/png_io.h"
#include "pipeline/dataset/trajectory_tum.h"
#include "tests/support/error_message.h"
#include "tests/support/log_capture.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {
namespace fs = std::filesystem;

class DatasetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("pensight_dataset_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  DatasetContents contents() const {
    DatasetContents c;
    c.scene = {0.025, 6.5, 0.3, MeshType::kDiamond, 1.2};
    c.cam0.camera.width_px = 36;
    c.cam0.camera.height_px = 27;
    c.cam0.camera.fx_px = 23.1;
    c.cam0.camera.fy_px = 23.2;
    c.cam0.camera.cx_px = 17.5;
    c.cam0.camera.cy_px = 13.25;
    c.cam0.camera.k1 = -0.05;
    c.cam0.camera.p2 = 1e-4;
    c.cam0.T_body_camera.linear() = rotation_from_rpy(0.1, -0.2, 1.4);
    c.cam0.T_body_camera.translation() = Eigen::Vector3d(0.3, -0.02, 0.1);
    DvlCalibration dvl;
    dvl.rate_hz = 4;
    dvl.T_body_dvl.linear() = rotation_from_rpy(0, 0.5, 0);
    for (size_t i = 0; i < 4; ++i) {
      const double a = 0.5 + std::numbers::pi / 2 * static_cast<double>(i);
      dvl.beam_directions_S[i] =
          Eigen::Vector3d(0.5 * std::cos(a), 0.5 * std::sin(a), 1).normalized();
    }
    c.dvl0 = dvl;
    return c;
  }

  ImageU8 random_frame(std::mt19937_64& rng, int w, int h) {
    ImageU8 img(w, h);
    for (auto& p : img.pixels) p = static_cast<uint8_t>(rng() & 0xff);
    return img;
  }

  fs::path dir_;
};

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

std::string read_file(const fs::path& p) {
  return read_file_bytes(p).value_or("(missing)");
}

size_t count_of(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST_F(DatasetTest, RoundTripKeepsEverySensorAndImage) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::uniform_real_distribution<double> u(-3, 3);
  const DatasetContents c = contents();
  const fs::path root = dir_ / "seq";
  std::vector<ImageU8> frames;
  std::vector<ImageU16> depths;
  std::vector<GroundTruthRow> truth;
  std::vector<DvlSample> dvl;
  std::vector<PressureSample> pressure;
  std::vector<AttitudeSample> attitude;
  {
    DatasetWriter w(root, c);
    for (int i = 0; i < 3; ++i) {
      const int64_t t = 1'700'000'000'000'000'000 + i * 100'000'000LL;
      frames.push_back(random_frame(rng, 36, 27));
      ImageU16 depth(36, 27);
      for (auto& p : depth.pixels) p = static_cast<uint16_t>(rng() & 0xffff);
      depths.push_back(depth);
      GroundTruthRow g{t,      {u(rng), u(rng), u(rng)}, u(rng),  u(rng), u(rng), u(rng),
                       u(rng), i == 1 ? kNaN : u(rng),   0.25 * i};
      truth.push_back(g);
      w.add_frame(t, frames.back());
      w.add_groundtruth(g, depth);
      DvlSample d{t + 1, {u(rng), u(rng), u(rng)}, i != 2, {u(rng), kNaN, u(rng), u(rng)}};
      dvl.push_back(d);
      w.add_dvl(d);
      pressure.push_back({t + 2, u(rng)});
      w.add_pressure(pressure.back());
      attitude.push_back({t + 3, u(rng), u(rng), u(rng)});
      w.add_attitude(attitude.back());
    }
    EXPECT_FALSE(fs::exists(root)) << "the dataset must appear only on finish()";
    w.finish();
  }
  const Dataset d = read_dataset(root);
  EXPECT_DOUBLE_EQ(d.scene.bar_length_m, 0.025);
  EXPECT_DOUBLE_EQ(d.scene.pen_radius_m, 6.5);
  ASSERT_TRUE(d.scene.initial_rho_rad);
  EXPECT_DOUBLE_EQ(*d.scene.initial_rho_rad, 0.3);
  EXPECT_EQ(d.scene.net_mesh_type, MeshType::kDiamond);
  ASSERT_TRUE(d.scene.net_mesh_angle_rad);
  EXPECT_NEAR(*d.scene.net_mesh_angle_rad, 1.2, 1e-9);  // written in degrees, 10 digits
  EXPECT_EQ(d.cam0.camera.width_px, 36);
  EXPECT_EQ(d.cam0.camera.height_px, 27);
  EXPECT_DOUBLE_EQ(d.cam0.camera.fy_px, 23.2);
  EXPECT_DOUBLE_EQ(d.cam0.camera.cy_px, 13.25);
  EXPECT_DOUBLE_EQ(d.cam0.camera.k1, -0.05);
  EXPECT_DOUBLE_EQ(d.cam0.camera.p2, 1e-4);
  EXPECT_TRUE(d.cam0.T_body_camera.isApprox(c.cam0.T_body_camera, 1e-8));
  ASSERT_TRUE(d.dvl0 && d.pressure0 && d.imu0 && d.groundtruth0);
  EXPECT_TRUE(d.dvl0->calibration.T_body_dvl.isApprox(c.dvl0->T_body_dvl, 1e-8));
  EXPECT_TRUE(d.dvl0->has_beam_ranges);
  ASSERT_EQ(d.frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(d.load_frame(i).pixels, frames[i].pixels);
    EXPECT_EQ(d.load_depth_mm(i).pixels, depths[i].pixels);
    const GroundTruthRow* g = d.truth_for_frame(i);
    ASSERT_NE(g, nullptr);
    EXPECT_NEAR(g->p_pen_body_m.x(), truth[i].p_pen_body_m.x(), 1e-8);
    EXPECT_NEAR(g->yaw_rad, truth[i].yaw_rad, 1e-8);
    EXPECT_NEAR(g->d_net_m, truth[i].d_net_m, 1e-8);
    EXPECT_EQ(std::isnan(g->pitch_net_rad), std::isnan(truth[i].pitch_net_rad));
    EXPECT_DOUBLE_EQ(g->net_fraction, truth[i].net_fraction);
    const DvlSample& s = d.dvl0->samples[i];
    EXPECT_EQ(s.timestamp_ns, dvl[i].timestamp_ns);
    EXPECT_NEAR(s.velocity_B_mps.z(), dvl[i].velocity_B_mps.z(), 1e-8);
    EXPECT_EQ(s.valid, dvl[i].valid);
    EXPECT_TRUE(std::isnan(s.beam_range_m[1]));
    EXPECT_NEAR(s.beam_range_m[3], dvl[i].beam_range_m[3], 1e-8);
    EXPECT_NEAR((*d.pressure0)[i].depth_m, pressure[i].depth_m, 1e-8);
    EXPECT_NEAR((*d.imu0)[i].pitch_rad, attitude[i].pitch_rad, 1e-8);
  }
  const ImageF32 depth_m = d.load_depth_m(0);
  const uint16_t mm = depths[0].pixels[5];
  if (mm == 0) {
    EXPECT_TRUE(std::isnan(depth_m.pixels[5]));
  } else {
    EXPECT_FLOAT_EQ(depth_m.pixels[5], mm * 1e-3f);
  }
}

TEST_F(DatasetTest, UnfinishedWriterLeavesNothing) {
  {
    DatasetWriter w(dir_ / "seq", contents());
    std::mt19937_64 rng(1);
    w.add_frame(10, random_frame(rng, 36, 27));
    EXPECT_TRUE(fs::exists(w.temporary_root()));
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

// A recorder killed mid-run: what it streamed reads back up to the last complete row, with the
// device times in their own column passed over by the reader.
TEST_F(DatasetTest, StreamingWriterLeavesAReadableDatasetWithoutFinish) {
  DatasetContents c = contents();
  c.groundtruth0 = false;
  c.device_times = true;
  std::mt19937_64 rng(9);
  const ImageU8 frame = random_frame(rng, 36, 27);
  {
    DatasetWriter w(dir_ / "rec", c, DatasetWriteMode::kStreaming);
    EXPECT_EQ(w.temporary_root(), dir_ / "rec");
    w.add_frame(100, frame);
    w.add_frame(200, random_frame(rng, 36, 27));
    DvlSample dvl;
    dvl.timestamp_ns = 150;
    dvl.velocity_B_mps = {0.25, -0.5, 0.125};
    dvl.valid = true;
    dvl.beam_range_m = {1.5, 1.25, kNaN, 2};
    dvl.device_ns = 1'700'000'000'123'000'000;
    w.add_dvl(dvl);
    w.add_pressure({120, 2.5, 77});
    w.add_attitude({130, 0.1, -0.2, 0.3});
    // Every row is on disk before the writer goes away, without finish().
    const Dataset mid = read_dataset(dir_ / "rec");
    EXPECT_EQ(mid.frames.size(), 2u);
    ASSERT_TRUE(mid.dvl0);
    EXPECT_EQ(mid.dvl0->samples.size(), 1u);
  }
  testing::LogCapture log;
  const Dataset d = read_dataset(dir_ / "rec");
  ASSERT_EQ(d.frames.size(), 2u);
  EXPECT_EQ(d.load_frame(0).pixels, frame.pixels);
  ASSERT_TRUE(d.dvl0 && d.dvl0->has_beam_ranges);
  const DvlSample& s = d.dvl0->samples.at(0);
  EXPECT_EQ(s.timestamp_ns, 150);
  EXPECT_EQ(s.velocity_B_mps, Eigen::Vector3d(0.25, -0.5, 0.125));
  EXPECT_EQ(s.beam_range_m[1], 1.25);
  EXPECT_TRUE(std::isnan(s.beam_range_m[2]));
  EXPECT_EQ(d.pressure0->at(0).depth_m, 2.5);
  EXPECT_EQ(d.imu0->at(0).yaw_rad, 0.3);
  EXPECT_TRUE(d.skipped_rows.empty());
  EXPECT_NE(log.text().find("dvl0/data.csv: columns after the first 9"), std::string::npos)
      << log.text();
  const std::string dvl_csv = read_file(dir_ / "rec" / "dvl0" / "data.csv");
  EXPECT_NE(dvl_csv.find("r4 [m],device_time [ns]\n"), std::string::npos) << dvl_csv;
  EXPECT_NE(dvl_csv.find(",1700000000123000000\n"), std::string::npos) << dvl_csv;
  EXPECT_NE(read_file(dir_ / "rec" / "pressure0" / "data.csv").find("120,2.5,77\n"),
            std::string::npos);
  EXPECT_NE(read_file(dir_ / "rec" / "imu0" / "attitude.csv").find(",nan\n"), std::string::npos);
  // No hidden partial frame is left beside the complete ones.
  for (const auto& e : fs::directory_iterator(dir_ / "rec" / "cam0" / "data")) {
    EXPECT_NE(e.path().filename().string().front(), '.') << e.path();
  }
  // A recording is never written over: not even an earlier one.
  EXPECT_NE(testing::error_message([&] {
              DatasetWriter(dir_ / "rec", c, DatasetWriteMode::kStreaming);
            }).find("exists and is not empty"),
            std::string::npos);
}

// Another tool's log with a column of its own after the contract's, and without beam ranges.
TEST_F(DatasetTest, ExtraColumnsOfOtherToolsArePassedOver) {
  const fs::path root = dir_ / "extra";
  {
    DatasetWriter w(root, contents());
    std::mt19937_64 rng(5);
    w.add_frame(100, random_frame(rng, 36, 27));
    w.finish();
  }
  write_file(root / "dvl0" / "data.csv",
             "#timestamp [ns],vx [m/s],vy [m/s],vz [m/s],valid,fom\n100,0.1,0,0,1,0.002\n"
             "200,0.2,0,0,1,0.003\n");
  write_file(root / "cam0" / "data.csv",
             "#timestamp [ns],filename,exposure [us]\n100," + frame_filename(100) + ",800\n");
  const Dataset d = read_dataset(root);
  ASSERT_EQ(d.dvl0->samples.size(), 2u);
  EXPECT_FALSE(d.dvl0->has_beam_ranges);
  EXPECT_EQ(d.dvl0->samples[1].velocity_B_mps.x(), 0.2);
  EXPECT_TRUE(std::isnan(d.dvl0->samples[1].beam_range_m[0]));
  EXPECT_EQ(d.frames.size(), 1u);
}

TEST_F(DatasetTest, ReplacesAnEarlierDatasetButNoOtherFolder) {
  std::mt19937_64 rng(2);
  for (int run = 0; run < 2; ++run) {
    DatasetWriter w(dir_ / "seq", contents());
    w.add_frame(10 + run, random_frame(rng, 36, 27));
    w.finish();
  }
  EXPECT_EQ(read_dataset(dir_ / "seq").frames.at(0).timestamp_ns, 11);
  fs::create_directories(dir_ / "photos");
  write_file(dir_ / "photos" / "holiday.jpg", "x");
  EXPECT_NE(testing::error_message([&] {
              DatasetWriter(dir_ / "photos", contents());
            }).find("not a dataset"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "photos" / "holiday.jpg"));
}

TEST_F(DatasetTest, WriterRefusesWrongSizeAndTimeOrder) {
  DatasetWriter w(dir_ / "seq", contents());
  std::mt19937_64 rng(3);
  EXPECT_NE(
      testing::error_message([&] { w.add_frame(5, random_frame(rng, 35, 27)); }).find("35x27"),
      std::string::npos);
  w.add_frame(5, random_frame(rng, 36, 27));
  EXPECT_NE(
      testing::error_message([&] { w.add_frame(5, random_frame(rng, 36, 27)); }).find("increase"),
      std::string::npos);
}

class DatasetFilesTest : public DatasetTest {
 protected:
  void SetUp() override {
    DatasetTest::SetUp();
    root_ = dir_ / "seq";
    DatasetContents c = contents();
    c.dvl0.reset();
    c.imu0 = false;
    DatasetWriter w(root_, c);
    std::mt19937_64 rng(4);
    w.add_frame(100, random_frame(rng, 36, 27));
    w.add_frame(200, random_frame(rng, 36, 27));
    w.finish();
  }
  fs::path root_;
};

TEST_F(DatasetFilesTest, MissingSensorFolderMeansAbsentSensor) {
  const Dataset d = read_dataset(root_);
  EXPECT_FALSE(d.dvl0);
  EXPECT_FALSE(d.imu0);
  EXPECT_TRUE(d.pressure0);
  EXPECT_EQ(d.frames.size(), 2u);
}

TEST_F(DatasetFilesTest, MissingFolderOrSensorYamlIsNamed) {
  EXPECT_NE(testing::error_message([&] { read_dataset(dir_ / "nope"); }).find("nope"),
            std::string::npos);
  fs::remove(root_ / "cam0" / "sensor.yaml");
  EXPECT_NE(testing::error_message([&] { read_dataset(root_); }).find("cam0/sensor.yaml"),
            std::string::npos);
}

TEST_F(DatasetFilesTest, BadYamlAndMissingKeysAreNamed) {
  const fs::path scene = root_ / "scene.yaml";
  write_file(scene, "net_mesh_size_m: [0.03\npen_radius_m: 12\n");
  EXPECT_NE(testing::error_message([&] { read_dataset(root_); }).find("not valid YAML"),
            std::string::npos);
  write_file(scene, "net_mesh_size_m: 0.03\n");
  std::string e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("'pen_radius_m': missing"), std::string::npos) << e;
  write_file(scene, "net_mesh_size_m: -0.03\npen_radius_m: 12\n");
  e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("scene.yaml: key 'net_mesh_size_m': -0.03 is outside > 0 m (bar length"),
            std::string::npos)
      << e;
  write_file(scene, "net_mesh_size_m: 0.03\npen_radius_m: 12\nnet_mesh_type: hexagonal\n");
  e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("'net_mesh_type': 'hexagonal' is not a mesh type"), std::string::npos) << e;
  write_file(scene, "net_mesh_size_m: 0.03\npen_radius_m: 12\nnet_mesh_angle_deg: 170\n");
  e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("'net_mesh_angle_deg': 170 is outside 30 to 150 deg"), std::string::npos) << e;
  write_file(scene, "net_mesh_size_m: 0.03\npen_radius_m: 12\n");
  write_file(root_ / "cam0" / "sensor.yaml", "sensor_type: camera\nrate_hz: 10\n");
  e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("'resolution': missing"), std::string::npos) << e;
}

// A flat panel round-trips through scene_yaml; its keys are checked and named.
TEST_F(DatasetFilesTest, FlatPanelSceneRoundTripsAndBadPanelsAreNamed) {
  const fs::path scene = root_ / "scene.yaml";
  SceneConfig s;
  s.pen_radius_m = 100;
  s.flat_panel =
      SceneConfig::FlatPanel{Eigen::Vector3d(3.5, -1.25, 0.5), Eigen::Vector3d(0.6, -0.8, 0)};
  write_file(scene, scene_yaml(s));
  const Dataset d = read_dataset(root_);
  ASSERT_TRUE(d.scene.flat_panel);
  EXPECT_TRUE(d.scene.flat_panel->plane_point_m.isApprox(s.flat_panel->plane_point_m, 1e-12));
  EXPECT_TRUE(d.scene.flat_panel->plane_normal.isApprox(s.flat_panel->plane_normal, 1e-12));
  const std::string base = "net_mesh_size_m: 0.03\npen_radius_m: 100\n";
  const std::pair<std::string, std::string> bad[] = {
      {"net_type: hexagon\n", "'net_type': 'hexagon' is not a net type"},
      {"net_type: flat_panel\nnet_plane_normal: [1, 0, 0]\n", "'net_plane_point_m': missing"},
      {"net_type: flat_panel\nnet_plane_point_m: [5, 0, 0]\n", "'net_plane_normal': missing"},
      {"net_type: flat_panel\nnet_plane_point_m: [5, 0, 0]\nnet_plane_normal: [2, 0, 0]\n",
       "'net_plane_normal': must be a unit vector"},
      {"net_type: flat_panel\nnet_plane_point_m: [5, 0, 0]\nnet_plane_normal: [0, 0, 1]\n",
       "'net_plane_normal': must be a unit vector within 10 deg of the horizontal"},
      {"net_type: flat_panel\nnet_plane_point_m: [5, 0, 0]\nnet_plane_normal: [-1, 0, 0]\n",
       "'net_plane_normal': must point away from the pen frame's origin"},
  };
  for (const auto& [text, expected] : bad) {
    write_file(scene, base + text);
    const std::string e = testing::error_message([&] { read_dataset(root_); });
    EXPECT_NE(e.find(expected), std::string::npos) << text << " -> " << e;
    EXPECT_NE(e.find("scene.yaml"), std::string::npos) << e;
  }
}

// Other tools write dataset files with keys of their own: they are read with one note per file
// naming them. The contract's flat-panel keys are read.
TEST_F(DatasetFilesTest, KeysOfOtherToolsAreReadWithOneNotePerFile) {
  write_file(root_ / "scene.yaml",
             "net_mesh_size_m: 0.031\n"
             "pen_radius_m: 25\n"
             "net_mesh_type: diamond\n"
             "net_mesh_angle_deg: 95\n"
             "net_type: flat_panel\n"
             "net_plane_point_m: [100.0, 0.0, 0.0]\n"
             "net_plane_normal: [1.0, 0.0, 0.0]\n"
             "initial_rho_rad: 0.25\n"
             "foo: {bar: 1}\n");
  write_file(root_ / "cam0" / "sensor.yaml",
             camera_yaml(contents().cam0) + "rostopic: /cam0/image_raw\n");
  testing::LogCapture log;
  const Dataset d = read_dataset(root_);
  EXPECT_DOUBLE_EQ(d.scene.bar_length_m, 0.031);
  EXPECT_DOUBLE_EQ(d.scene.pen_radius_m, 25);
  ASSERT_TRUE(d.scene.initial_rho_rad);
  EXPECT_DOUBLE_EQ(*d.scene.initial_rho_rad, 0.25);
  EXPECT_EQ(d.scene.net_mesh_type, MeshType::kDiamond);
  ASSERT_TRUE(d.scene.net_mesh_angle_rad);
  EXPECT_NEAR(*d.scene.net_mesh_angle_rad, deg_to_rad(95), 1e-12);
  EXPECT_DOUBLE_EQ(d.cam0.camera.fx_px, 23.1);
  EXPECT_EQ(count_of(log.text(), "keys not used by pensight"), 2u) << log.text();
  ASSERT_TRUE(d.scene.flat_panel);
  EXPECT_EQ(d.scene.flat_panel->plane_point_m, Eigen::Vector3d(100, 0, 0));
  EXPECT_EQ(d.scene.flat_panel->plane_normal, Eigen::Vector3d(1, 0, 0));
  EXPECT_NE(log.text().find("scene.yaml: keys not used by pensight: foo\n"), std::string::npos)
      << log.text();
  EXPECT_NE(log.text().find("sensor.yaml: keys not used by pensight: rostopic\n"),
            std::string::npos)
      << log.text();
}

TEST_F(DatasetTest, DvlBeamsAsListReadLikeTheMatrix) {
  const DvlCalibration dvl = *contents().dvl0;
  const fs::path matrix_file = dir_ / "matrix.yaml";
  write_file(matrix_file, dvl_yaml(dvl));
  std::string list = "beam_directions:\n";
  for (const auto& b : dvl.beam_directions_S) {
    list += "  - [" + format_number(b.x()) + ", " + format_number(b.y()) + ", " +
            format_number(b.z()) + "]\n";
  }
  std::string text = dvl_yaml(dvl);
  text = text.substr(0, text.find("beam_directions:")) + list + "T_BD: {}\n";
  const fs::path list_file = dir_ / "list.yaml";
  write_file(list_file, text);
  testing::LogCapture log;
  const DvlCalibration a = read_dvl_yaml(matrix_file);
  const DvlCalibration b = read_dvl_yaml(list_file);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(a.beam_directions_S[i], b.beam_directions_S[i]) << i;
    EXPECT_NEAR((a.beam_directions_S[i] - dvl.beam_directions_S[i]).norm(), 0, 1e-8) << i;
  }
  EXPECT_EQ(a.T_body_dvl.matrix(), b.T_body_dvl.matrix());
  EXPECT_EQ(a.rate_hz, b.rate_hz);
  EXPECT_EQ(log.text(), list_file.string() + ": keys not used by pensight: T_BD\n");
}

TEST_F(DatasetTest, MalformedDvlBeamsNameTheKeyAndBothForms) {
  const std::string head =
      "sensor_type: dvl\nrate_hz: 4\n"
      "T_BS: {cols: 4, rows: 4, data: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}\n";
  const fs::path file = dir_ / "sensor.yaml";
  const auto error_for = [&](const std::string& beams) {
    write_file(file, head + "beam_directions: " + beams + "\n");
    return testing::error_message([&] { read_dvl_yaml(file); });
  };
  for (const char* beams :
       {"[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0]]",
        "[1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0]", "{cols: 3, rows: 3, data: [1,0,0, 0,1,0, 0,0,1]}",
        "up"}) {
    const std::string e = error_for(beams);
    EXPECT_NE(e.find("sensor.yaml: key 'beam_directions': expected 4 unit vectors"),
              std::string::npos)
        << beams << ": " << e;
    EXPECT_NE(e.find("{cols: 3, rows: 4, data: [12 numbers, row-major]}"), std::string::npos) << e;
    EXPECT_NE(e.find("[[x, y, z], [x, y, z], [x, y, z], [x, y, z]]"), std::string::npos) << e;
  }
  std::string e = error_for("[[1, 0, 0], [0, 1, 0], [0, 0, one], [1, 0, 0]]");
  EXPECT_NE(e.find("'beam_directions': expected a finite number, got 'one'"), std::string::npos)
      << e;
  e = error_for("{cols: 3, rows: 4, data: [1,0,0, 0,1,0, 0,0,x, 1,0,0]}");
  EXPECT_NE(e.find("'beam_directions.data': expected a finite number, got 'x'"), std::string::npos)
      << e;
  e = error_for("[[1, 0, 0], [0, 1, 0], [0, 0, 2], [1, 0, 0]]");
  EXPECT_NE(e.find("'beam_directions': each beam must be a unit vector"), std::string::npos) << e;
}

TEST_F(DatasetFilesTest, DatasetWithoutFramesIsRefused) {
  write_file(root_ / "cam0" / "data.csv", "#timestamp [ns],filename\n");
  const std::string e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("cam0/data.csv: lists no camera frames"), std::string::npos) << e;
}

// A logger glitch in a long log: each kind of bad row (a field that is not a number, a wrong
// field count, a timestamp that goes back) is skipped, counted and named with its line.
TEST_F(DatasetFilesTest, BadSensorLogRowsAreSkippedCountedAndNamed) {
  std::string dvl = "#timestamp [ns],vx,vy,vz,valid\n", pressure = "#timestamp [ns],depth [m]\n",
              attitude = "#timestamp [ns],roll,pitch,yaw\n";
  for (int i = 1; i <= 20; ++i) {
    const std::string t = std::to_string(i * 100);
    dvl += t + ",0.1,0,0,1\n";
    pressure += t + ",1.5\n";
    attitude += t + ",0,0,0.1\n";
  }
  dvl += "2100,0.1,0\n2200,0.1,0,0,1\n";  // line 22: 3 fields
  pressure += "2100,abc\n2200,1.5\n";     // line 22: not a number
  attitude += "50,0,0,0\n2200,0,0,0\n";   // line 22: back in time
  const fs::path root = dir_ / "logs";
  {
    DatasetWriter w(root, contents());  // with dvl0/ and imu0/
    std::mt19937_64 rng(5);
    w.add_frame(100, random_frame(rng, 36, 27));
    w.finish();
  }
  write_file(root / "dvl0" / "data.csv", dvl);
  write_file(root / "pressure0" / "data.csv", pressure);
  write_file(root / "imu0" / "attitude.csv", attitude);
  testing::LogCapture log;
  const Dataset d = read_dataset(root);
  EXPECT_EQ(d.dvl0->samples.size(), 21u);
  EXPECT_EQ(d.pressure0->size(), 21u);
  EXPECT_EQ(d.imu0->size(), 21u);
  ASSERT_EQ(d.skipped_rows.size(), 3u);
  for (const SkippedRows& s : d.skipped_rows) {
    EXPECT_EQ(s.skipped, 1u) << s.file;
    EXPECT_EQ(s.rows, 22u) << s.file;
  }
  EXPECT_NE(
      log.text().find("dvl0/data.csv:22: expected at least 5 comma-separated fields, got 3; row "
                      "skipped"),
      std::string::npos)
      << log.text();
  EXPECT_NE(log.text().find("pressure0/data.csv:22: field 2: expected a number"), std::string::npos)
      << log.text();
  EXPECT_NE(log.text().find("attitude.csv:22: timestamp repeats or goes back in time"),
            std::string::npos)
      << log.text();
  EXPECT_NE(log.text().find("pressure0/data.csv: 1 of 22 rows skipped"), std::string::npos)
      << log.text();
}

// A log with more bad rows than good ones is in another format: the run stops, naming the first.
TEST_F(DatasetFilesTest, MostlyBadSensorLogIsRefusedNamingTheFirstBadRow) {
  write_file(root_ / "pressure0" / "data.csv",
             "#timestamp [ns],depth [m]\n\n100,1.5\n200,abc\n300;1.5\n");
  const std::string e = testing::error_message([&] { read_dataset(root_); });
  EXPECT_NE(e.find("data.csv:4: field 2: expected a number (or nan), got 'abc' (2 of 3 rows are "
                   "bad"),
            std::string::npos)
      << e;
}

TEST_F(DatasetFilesTest, WrongImageSizeIsRefusedOnLoad) {
  const Dataset d = read_dataset(root_);
  cv::imwrite((root_ / "cam0" / "data" / d.frames[1].filename).string(),
              cv::Mat(20, 30, CV_8UC1, cv::Scalar(7)));
  EXPECT_NO_THROW(d.load_frame(0));
  EXPECT_NE(testing::error_message([&] { d.load_frame(1); }).find("30x20"), std::string::npos);
  fs::remove(root_ / "cam0" / "data" / d.frames[0].filename);
  EXPECT_NE(testing::error_message([&] { d.load_frame(0); }).find("not found"), std::string::npos);
}

// A damaged header claiming gigapixels is refused before the decoder allocates them.
TEST_F(DatasetFilesTest, PngClaimingAHugeSizeIsRefusedBeforeDecoding) {
  const Dataset d = read_dataset(root_);
  const fs::path file = root_ / "cam0" / "data" / d.frames[0].filename;
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(bytes.size(), 24u);
  for (const size_t at : {size_t{16}, size_t{20}}) bytes.replace(at, 4, "\x00\x01\x86\xa0", 4);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << bytes;
  }
  EXPECT_NE(
      testing::error_message([&] { read_png_grey8(file); }).find("100000x100000, larger than"),
      std::string::npos);
  EXPECT_NE(testing::error_message([&] {
              d.load_frame(0);
            }).find("100000x100000 but sensor.yaml says 36x27"),
            std::string::npos);
  // Other formats OpenCV could decode (a BMP here) are not read: dataset images are PNG.
  std::vector<uchar> bmp;
  cv::imencode(".bmp", cv::Mat(27, 36, CV_8UC1, cv::Scalar(9)), bmp);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bmp.data()), static_cast<std::streamsize>(bmp.size()));
  }
  EXPECT_NE(testing::error_message([&] { d.load_frame(0); }).find("is not a PNG file"),
            std::string::npos);
}

TEST_F(DatasetFilesTest, ColourAndSixteenBitFramesBecomeGrey8) {
  const Dataset d = read_dataset(root_);
  cv::Mat colour(27, 36, CV_8UC3, cv::Scalar(10, 200, 60));  // B, G, R
  cv::imwrite((root_ / "cam0" / "data" / d.frames[0].filename).string(), colour);
  const ImageU8 grey = d.load_frame(0);
  EXPECT_NEAR(grey.at(3, 4), 0.114 * 10 + 0.587 * 200 + 0.299 * 60, 1.0);
  cv::Mat wide(27, 36, CV_16UC1, cv::Scalar(257 * 123));
  cv::imwrite((root_ / "cam0" / "data" / d.frames[1].filename).string(), wide);
  EXPECT_EQ(d.load_frame(1).at(35, 26), 123);
}

// The header line and the first data row of a CSV file.
std::pair<std::string, std::string> header_and_first_row(const fs::path& file) {
  std::ifstream in(file);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  return {header, row};
}

TEST_F(DatasetTest, EstimatesCsvHasContractColumnsAndNan) {
  const fs::path file = dir_ / "estimates.csv";
  {
    EstimatesCsvWriter w(file);
    EstimateRow r;
    r.timestamp_ns = 42;
    r.d_net_fft_m = 1.25;
    r.valid_rois = 17;
    w.write(r);
    EXPECT_FALSE(fs::exists(file));
    w.finish();
  }
  const auto [header, row] = header_and_first_row(file);
  EXPECT_EQ(header,
            "#timestamp [ns],d_net_fft [m],psi_net_fft [rad],pitch_net_fft [rad],d_net_depth [m],"
            "psi_net_depth [rad],pitch_net_depth [rad],r_g [m],rho_g [rad],z_g [m],psi_g [rad],"
            "valid_rois");
  EXPECT_EQ(row, "42,1.25,nan,nan,nan,nan,nan,nan,nan,nan,nan,17");
  const auto rows = read_estimates_csv(file);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].valid_rois, 17);
  EXPECT_TRUE(std::isnan(rows[0].psi_g_rad));
  { EstimatesCsvWriter unfinished(dir_ / "other.csv"); }
  EXPECT_FALSE(fs::exists(dir_ / "other.csv"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

// OUT/global_pose_published.csv: its columns, NaN, read back as EstimateRow with only the
// global-pose fields, written whole, and a malformed file named in the error.
TEST_F(DatasetTest, PublishedGlobalPoseCsvRoundTrip) {
  const fs::path file = dir_ / kPublishedGlobalPoseFile;
  {
    GlobalPoseCsvWriter w(file);
    EstimateRow r;
    r.timestamp_ns = 7;
    r.r_g_m = 11.25;
    r.rho_g_rad = -0.5;
    r.z_g_m = 3.5;
    r.d_net_fft_m = 1.0;  // not a column of this file
    w.write(r);
    r.timestamp_ns = 8;
    r.rho_g_rad = kNaN;
    w.write(r);
    EXPECT_FALSE(fs::exists(file));
    w.finish();
  }
  const auto [header, row] = header_and_first_row(file);
  EXPECT_EQ(header, "#timestamp [ns],r_g [m],rho_g [rad],z_g [m],psi_g [rad]");
  EXPECT_EQ(row, "7,11.25,-0.5,3.5,nan");
  const auto rows = read_global_pose_csv(file);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].timestamp_ns, 8);
  EXPECT_DOUBLE_EQ(rows[0].r_g_m, 11.25);
  EXPECT_DOUBLE_EQ(rows[0].rho_g_rad, -0.5);
  EXPECT_TRUE(std::isnan(rows[1].rho_g_rad));
  EXPECT_TRUE(std::isnan(rows[0].psi_g_rad));
  EXPECT_TRUE(std::isnan(rows[0].d_net_fft_m));
  { GlobalPoseCsvWriter unfinished(dir_ / "other.csv"); }
  EXPECT_FALSE(fs::exists(dir_ / "other.csv"));
  std::ofstream(dir_ / "short.csv") << "#header\n1,2,3,4\n";
  try {
    read_global_pose_csv(dir_ / "short.csv");
    FAIL() << "a 4-column row was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.csv"), std::string::npos) << e.what();
  }
}

// OUT/trajectory_tum.txt: the exact text of known poses (nanoseconds kept, qw >= 0 where Eigen's
// conversion gives qw < 0 for a 200 deg yaw), poses with a NaN left out, written whole, read back,
// and a malformed line named in the error.
TEST_F(DatasetTest, TrajectoryTumText) {
  const fs::path file = dir_ / kTrajectoryTumFile;
  Eigen::Isometry3d yawed = Eigen::Isometry3d::Identity();
  yawed.linear() = rotation_from_rpy(0, 0, deg_to_rad(200));
  yawed.translation() = Eigen::Vector3d(1.5, -2.25, 3);
  Eigen::Isometry3d rolled = Eigen::Isometry3d::Identity();
  rolled.linear() = rotation_from_rpy(std::numbers::pi / 2, 0, 0);
  Eigen::Isometry3d unknown = Eigen::Isometry3d::Identity();
  unknown.matrix().setConstant(kNaN);
  Eigen::Isometry3d half_known = yawed;
  half_known.translation().x() = kNaN;
  {
    TrajectoryTumWriter w(file);
    EXPECT_TRUE(w.write(1'700'000'000'123'456'789, yawed));
    EXPECT_FALSE(w.write(1'700'000'000'223'456'789, unknown));
    EXPECT_FALSE(w.write(1'700'000'000'323'456'789, half_known));
    EXPECT_TRUE(w.write(-1'500'000'000, rolled));
    EXPECT_TRUE(w.write(5, rolled));
    EXPECT_FALSE(fs::exists(file));
    w.finish();
  }
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text,
            "1700000000.123456789 1.5 -2.25 3 0 0 -0.984807753 0.173648178\n"
            "-1.500000000 0 0 0 0.707106781 0 0 0.707106781\n"
            "0.000000005 0 0 0 0.707106781 0 0 0.707106781\n");
  const std::vector<TumPose> poses = read_trajectory_tum(file);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[0].timestamp_ns, 1'700'000'000'123'456'789);
  EXPECT_EQ(poses[1].timestamp_ns, -1'500'000'000);
  EXPECT_EQ(poses[2].timestamp_ns, 5);
  EXPECT_EQ(poses[0].p_m, yawed.translation());
  // 9 significant digits: the rotation comes back within 1e-8 rad.
  EXPECT_LT(poses[0].q.angularDistance(Eigen::Quaterniond(yawed.linear())), 1e-8);
  EXPECT_LT(poses[2].q.angularDistance(Eigen::Quaterniond(rolled.linear())), 1e-8);
  { TrajectoryTumWriter unfinished(dir_ / "other.txt"); }
  EXPECT_FALSE(fs::exists(dir_ / "other.txt"));
  // What other tools write: comments, blank lines, tabs, an exponent.
  std::ofstream(dir_ / "foreign.txt") << "# t x y z qx qy qz qw\n\n1.5e0\t1 2 3  0 0 0 1\n";
  const std::vector<TumPose> foreign = read_trajectory_tum(dir_ / "foreign.txt");
  ASSERT_EQ(foreign.size(), 1u);
  EXPECT_EQ(foreign[0].timestamp_ns, 1'500'000'000);
  EXPECT_EQ(foreign[0].p_m, Eigen::Vector3d(1, 2, 3));
  std::ofstream(dir_ / "short.txt") << "1.0 2 3 4 0 0 0\n";
  try {
    read_trajectory_tum(dir_ / "short.txt");
    FAIL() << "a 7-field line was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.txt:1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pensight
