// Datasets written by generate_dataset: readable with read_dataset, d_net equal to the depth
// image at the principal point, deterministic per seed, sensors consistent with the trajectory,
// and nothing left behind when a run fails.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "sim/frame_state.h"
#include "sim/generate.h"
#include "sim/sensors.h"
#include "sim/trajectory.h"

namespace pensight::sim {
namespace {
namespace fs = std::filesystem;

Scenario small_sweep(double duration_s) {
  const char* root = std::getenv("PENSIGHT_SOURCE_DIR");
  Scenario s = load_scenario(std::string(root ? root : ".") + "/scenarios/sweep.yaml");
  PinholeCamera& k = s.camera.calibration.camera;
  k = k.scaled(96.0 / 720.0);
  s.duration_s = duration_s;
  validate(s);
  return s;
}

class GenerateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pensight_generate_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

double bilinear(const ImageU16& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto v = [&](int dx, int dy) { return static_cast<double>(img.at(x0 + dx, y0 + dy)); };
  return (1 - fy) * ((1 - fx) * v(0, 0) + fx * v(1, 0)) + fy * ((1 - fx) * v(0, 1) + fx * v(1, 1));
}

TEST_F(GenerateTest, DatasetReadsBackAndDnetEqualsDepthAtPrincipalPoint) {
  const Scenario s = small_sweep(6.0);
  auto renderer = make_cpu_renderer(s, {});
  generate_dataset(s, *renderer, dir_ / "sweep");
  const Dataset d = read_dataset(dir_ / "sweep");
  ASSERT_EQ(d.frames.size(), 61u);
  ASSERT_TRUE(d.groundtruth0 && d.groundtruth0->has_depth && d.dvl0 && d.pressure0 && d.imu0);
  EXPECT_EQ(d.dvl0->samples.size(), 25u);
  EXPECT_EQ(d.pressure0->size(), 61u);
  EXPECT_EQ(d.imu0->size(), 121u);
  EXPECT_DOUBLE_EQ(d.scene.bar_length_m, 0.03);
  const PinholeCamera& cam = d.cam0.camera;
  int with_net = 0, without = 0;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    const GroundTruthRow* g = d.truth_for_frame(i);
    ASSERT_NE(g, nullptr);
    const ImageU16 depth = d.load_depth_mm(i);
    const auto nearest = depth.at(static_cast<int>(std::lround(cam.cx_px)),
                                  static_cast<int>(std::lround(cam.cy_px)));
    if (std::isnan(g->d_net_m)) {
      ++without;
      EXPECT_EQ(nearest, 0) << "frame " << i;
    } else {
      ++with_net;
      EXPECT_NEAR(bilinear(depth, cam.cx_px, cam.cy_px), g->d_net_m * 1000, 2.0) << "frame " << i;
      EXPECT_GT(g->net_fraction, 0.0);
    }
  }
  // The sweep starts and ends turned away from the net.
  EXPECT_GE(without, 4);
  EXPECT_GE(with_net, 45);
  EXPECT_TRUE(std::isnan(d.truth_for_frame(0)->d_net_m));
  EXPECT_TRUE(std::isnan(d.truth_for_frame(60)->d_net_m));
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(GenerateTest, SameSeedGivesIdenticalFiles) {
  const Scenario s = small_sweep(0.5);
  for (const char* name : {"a", "b"}) {
    auto renderer = make_cpu_renderer(s, {});
    generate_dataset(s, *renderer, dir_ / name);
  }
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "a")) {
    if (!e.is_regular_file()) continue;
    ++files;
    const fs::path rel = fs::relative(e.path(), dir_ / "a");
    EXPECT_EQ(read_all(e.path()), read_all(dir_ / "b" / rel)) << rel;
  }
  EXPECT_EQ(files, 21u);  // 3 yaml, 6 csv (groundtruth0/mesh.csv too), 6 frames, 6 depth images
  // groundtruth0/mesh.csv: the header and one row per frame.
  const std::string mesh = read_all(dir_ / "a" / "groundtruth0" / "mesh.csv");
  EXPECT_EQ(std::count(mesh.begin(), mesh.end(), '\n'), 7);
  EXPECT_EQ(mesh.rfind("#timestamp [ns],mesh_type,opening_angle [deg],stretch\n", 0), 0u);
}

// net_changes: the frames from a change's time on are rendered with the new net and their mesh
// truth is that net's.
TEST_F(GenerateTest, AChangingNetIsRenderedAndTruthedFromItsFrameOn) {
  Scenario s = small_sweep(1.0);
  NetChange change;
  change.t_s = 0.5;
  change.net = s.net;
  change.net.mesh_type = MeshType::kDiamond;
  change.net.opening_angle_deg = 75;
  s.net_changes = {change};
  auto renderer = make_cpu_renderer(s, {});
  generate_dataset(s, *renderer, dir_ / "changing");
  const Dataset d = read_dataset(dir_ / "changing");
  ASSERT_EQ(d.frames.size(), 11u);
  const std::string mesh = read_all(dir_ / "changing" / "groundtruth0" / "mesh.csv");
  const auto rows_with = [&](const std::string& word) {
    size_t n = 0;
    for (size_t at = mesh.find(word); at != std::string::npos; at = mesh.find(word, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(rows_with(",square,"), 5u);    // frames 0-4
  EXPECT_EQ(rows_with(",diamond,7"), 6u);  // frames 5-10
  // Frame 5 is the change's net's; frame 4 the first net's.
  for (const int frame : {4, 5}) {
    SCOPED_TRACE(frame);
    const FrameState f = frame_state(s, frame);
    const ImageU8 written = d.load_frame(static_cast<size_t>(frame));
    const ImageU8 in_view = make_cpu_renderer(s.with_net_at(f.t_s), {})->render(f).image;
    const ImageU8 other =
        make_cpu_renderer(s.with_net_at(frame == 5 ? 0.0 : 0.5), {})->render(f).image;
    EXPECT_EQ(written.pixels, in_view.pixels);
    EXPECT_NE(written.pixels, other.pixels);
  }
}

class FailingRenderer : public FrameRenderer {
 public:
  explicit FailingRenderer(std::unique_ptr<FrameRenderer> inner) : inner_(std::move(inner)) {}
  RenderedFrame render(const FrameState& f) override {
    if (f.frame == 3) throw Error("device lost");
    return inner_->render(f);
  }
  const char* name() const override { return "failing"; }

 private:
  std::unique_ptr<FrameRenderer> inner_;
};

TEST_F(GenerateTest, FailedRunLeavesNoDataset) {
  const Scenario s = small_sweep(1.0);
  FailingRenderer renderer(make_cpu_renderer(s, {}));
  EXPECT_THROW(generate_dataset(s, renderer, dir_ / "sweep"), Error);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(GenerateTest, SensorsFollowTheTrajectory) {
  Scenario s = small_sweep(8.0);
  s.dvl.velocity_noise_mps = 0;
  s.dvl.range_noise_m = 0;
  s.dvl.dropout_probability = 0;
  s.dvl.spike_probability = 0;
  const NetGeometry net(s.pen, s.net);
  const DvlCalibration calib = dvl_calibration(s.dvl);
  int ranges = 0;
  for (const DvlSample& d : simulate_dvl(s, net)) {
    const double t = seconds_between(s.start_time_ns, d.timestamp_ns);
    const BodyState b = body_state(s, t);
    const Eigen::Isometry3d T = b.T_pen_body * calib.T_body_dvl;
    for (size_t k = 0; k < 4; ++k) {
      if (std::isnan(d.beam_range_m[k])) continue;
      ++ranges;
      const Eigen::Vector3d end =
          T.translation() + d.beam_range_m[k] * (T.linear() * calib.beam_directions_S[k]);
      // kBulgeIterations fixed-point steps leave well under a millimetre on the bulge.
      EXPECT_NEAR(net.clearance(end), 0.0, 1e-3) << "beam " << k << " at " << t << " s";
    }
    if (d.valid) {
      const Eigen::Vector3d v = b.T_pen_body.linear().transpose() * b.velocity_pen_mps;
      EXPECT_LT((d.velocity_B_mps - v).norm(), 1e-9);
    }
  }
  EXPECT_GT(ranges, 60);

  s.dvl.dropout_probability = 0.3;
  s.waypoints = {Waypoint{.net_distance_m = 1.0, .depth_m = 3}};  // facing the net: all beams hit
  s.duration_s = 60;
  int invalid = 0, total = 0;
  for (const DvlSample& d : simulate_dvl(s, net)) {
    ++total;
    invalid += d.valid ? 0 : 1;
  }
  EXPECT_NEAR(static_cast<double>(invalid) / total, 0.3, 0.1);

  double bias = 0;
  const auto p = simulate_pressure(s);
  for (const PressureSample& q : p) {
    const double t = seconds_between(s.start_time_ns, q.timestamp_ns);
    bias += q.depth_m - body_state(s, t).T_pen_body.translation().z();
  }
  EXPECT_NEAR(bias / static_cast<double>(p.size()), s.pressure.bias_m,
              4 * s.pressure.noise_m / std::sqrt(static_cast<double>(p.size())));
}

// Scale error, offset and the injected spikes land where the scenario says, on nothing else.
TEST_F(GenerateTest, DvlScaleErrorOffsetAndInjectedSpike) {
  Scenario s = small_sweep(8.0);
  s.waypoints = {Waypoint{.t_s = 0, .along_m = 0, .net_distance_m = 1.0, .depth_m = 3},
                 Waypoint{.t_s = 8, .along_m = 2.4, .net_distance_m = 1.0, .depth_m = 3}};
  s.dvl.velocity_noise_mps = 0;
  s.dvl.dropout_probability = 0;
  s.dvl.spike_probability = 0;
  s.dvl.scale_error = 0.01;
  s.dvl.bias_B_mps = {0.004, -0.002, 0.001};
  s.dvl.spikes = {DvlSpike{.t_s = 3.0, .duration_s = 0.5, .velocity_B_mps = {0, 2.0, 0}}};
  validate(s);
  const NetGeometry net(s.pen, s.net);
  int spiked = 0, valid = 0;
  for (const DvlSample& d : simulate_dvl(s, net)) {
    if (!d.valid) continue;
    ++valid;
    const double t = seconds_between(s.start_time_ns, d.timestamp_ns);
    const BodyState b = body_state(s, t);
    Eigen::Vector3d v =
        1.01 * (b.T_pen_body.linear().transpose() * b.velocity_pen_mps) + s.dvl.bias_B_mps;
    if (t >= 3.0 - 1e-6 && t < 3.5 - 1e-6) {
      v += Eigen::Vector3d(0, 2.0, 0);
      ++spiked;
    }
    EXPECT_LT((d.velocity_B_mps - v).norm(), 1e-9) << "at " << t << " s";
  }
  EXPECT_EQ(spiked, 2);  // 4 Hz: 3.0 and 3.25 s
  EXPECT_GT(valid, 30);
}

}  // namespace
}  // namespace pensight::sim
