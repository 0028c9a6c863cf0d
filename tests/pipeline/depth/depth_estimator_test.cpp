// The depth stage: its three backends give one answer on a model of the contract; the pose from
// dense depth recovers a rendered plane; bad models, sizes and frames without priors get a clear
// error or a reason, never a crash.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <utility>

#include "core/error.h"
#include "kernels/nn/nn_models.h"
#include "kernels/nn/nn_onnx.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/depth_input.h"
#include "pipeline/depth/prior_surface.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/depth_models.h"
#include "tests/support/net_image.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

// Every way the network runs: both CPU libraries and the Vulkan executor.
constexpr std::pair<Backend, CpuInference> kEveryInference[] = {
    {Backend::kCpu, CpuInference::kEngine},
    {Backend::kCpu, CpuInference::kOpenCv},
    {Backend::kVulkan, CpuInference::kAuto}};
namespace fs = std::filesystem;

class DepthEstimatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("pensight_depth_estimator_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const kernels::Graph& g, const std::string& name) {
    const fs::path file = dir_ / name;
    kernels::export_onnx(g, file);
    return file;
  }

  fs::path s1_model(int w, int h) {
    const fs::path file = dir_ / "s1.onnx";
    testing::write_s1_depth_model(file, w, h);
    return file;
  }

  fs::path dir_;
};

// A rendered plane and its FFT priors.
struct Frame {
  ImageU8 image;
  std::vector<SparseDepth> priors;
  testing::NetScene scene;
};

Frame plane_frame(const PinholeCamera& cam, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<> u(-1, 1);
  Frame f;
  f.scene = {.distance_m = 1.0 + 0.5 * u(rng),
             .psi_rad = 0.35 * u(rng),
             .pitch_rad = 0.2 * u(rng),
             .seed = rng()};
  f.image = testing::render_net(cam, f.scene);
  NetDetector detector(cam, {.backend = Backend::kCpu, .cpu_threads = 2}, testing::test_device());
  f.priors = detector.detect(f.image).depths;
  return f;
}

TEST_F(DepthEstimatorTest, BackendsAgreeOnTheContract) {
  const PinholeCamera cam;
  // A random network of the contract at 64x48 (the camera's aspect), small enough for lavapipe.
  const fs::path model =
      write(kernels::compact_depth_net({64, 48}, testing::fresh_seed()), "net.onnx");
  const Frame f = plane_frame(cam, testing::fresh_seed());
  ASSERT_FALSE(f.priors.empty());
  std::vector<ImageF32> outputs;
  for (const auto& [backend, inference] : kEveryInference) {
    DepthEstimator estimator(cam, {.model = model, .backend = backend, .cpu_inference = inference},
                             testing::test_device());
    EXPECT_EQ(estimator.backend(), backend) << estimator.description();
    if (backend == Backend::kCpu) {
      EXPECT_EQ(estimator.cpu_inference(), inference);
    }
    const DenseDepth d = estimator.estimate(f.image, f.priors);
    ASSERT_TRUE(d.reason.empty()) << d.reason;
    ASSERT_EQ(d.depth_m.width, cam.width_px);
    outputs.push_back(d.depth_m);
  }
  for (size_t k = 1; k < outputs.size(); ++k) {
    double num = 0, den = 0;
    for (size_t i = 0; i < outputs[0].pixels.size(); ++i) {
      ASSERT_TRUE(std::isfinite(outputs[k].pixels[i])) << "backend " << k << " pixel " << i;
      num += std::pow(outputs[k].pixels[i] - outputs[0].pixels[i], 2);
      den += std::pow(outputs[0].pixels[i], 2);
    }
    EXPECT_LT(std::sqrt(num / den), 1e-4) << "backend " << k;
  }
}

// A model with the three-channel prior gets the prior surface of the frame's priors in its third
// channel on every backend: a model that returns that channel gives back the surface.
TEST_F(DepthEstimatorTest, ThirdPriorChannelIsThePriorSurface) {
  const PinholeCamera cam;
  const fs::path model = dir_ / "surface.onnx";
  testing::write_surface_depth_model(model, 64, 48);
  const Frame f = plane_frame(cam, testing::fresh_seed());
  ASSERT_FALSE(f.priors.empty());
  std::vector<float> small(64 * 48);
  render_prior_surface(
      fit_prior_surface(
          network_depths(f.priors, network_view(cam.width_px, cam.height_px, 64, 48), 64, 48), 64,
          48),
      small);
  // Bilinear about pixel centres, clamped at the border, as the stage resizes.
  ImageF32 expected(cam.width_px, cam.height_px);
  auto source = [](int i, double scale, int n, int& i0, double& frac) {
    const double s = std::clamp((i + 0.5) * scale - 0.5, 0.0, n - 1.0);
    i0 = std::min(static_cast<int>(s), n - 2);
    frac = s - i0;
  };
  for (int y = 0; y < cam.height_px; ++y) {
    int y0;
    double fy;
    source(y, 48.0 / cam.height_px, 48, y0, fy);
    for (int x = 0; x < cam.width_px; ++x) {
      int x0;
      double fx;
      source(x, 64.0 / cam.width_px, 64, x0, fx);
      auto at = [&](int dx, int dy) { return small[(y0 + dy) * 64 + x0 + dx]; };
      expected.at(x, y) = static_cast<float>((1 - fy) * ((1 - fx) * at(0, 0) + fx * at(1, 0)) +
                                             fy * ((1 - fx) * at(0, 1) + fx * at(1, 1)));
    }
  }
  for (const auto& [backend, inference] : kEveryInference) {
    DepthEstimator estimator(cam, {.model = model, .backend = backend, .cpu_inference = inference},
                             testing::test_device());
    const DenseDepth d = estimator.estimate(f.image, f.priors);
    ASSERT_TRUE(d.reason.empty()) << d.reason;
    double num = 0, den = 0;
    for (size_t i = 0; i < expected.pixels.size(); ++i) {
      num += std::pow(d.depth_m.pixels[i] - expected.pixels[i], 2);
      den += std::pow(expected.pixels[i], 2);
    }
    // The stage's alignment to the priors moves a surface fitted through them a little:
    // measured 2.1e-4 to 1.7e-3 over 16 seeds. A third channel left empty or holding S2 is off
    // by tens of per cent (on this plane S1 comes within 0.3-2 %, too close to tell apart).
    EXPECT_LT(std::sqrt(num / den), 4e-3) << estimator.description();
  }
}

TEST_F(DepthEstimatorTest, PlaneFromDenseDepthRecoversTheNet) {
  const PinholeCamera cam;
  DepthEstimator estimator(cam,
                           {.model = s1_model(320, 240),
                            .backend = Backend::kCpu,
                            .cpu_inference = CpuInference::kEngine},
                           testing::test_device());
  std::mt19937_64 rng(testing::fresh_seed());
  for (int trial = 0; trial < 3; ++trial) {
    const Frame f = plane_frame(cam, rng());
    ASSERT_FALSE(f.priors.empty());
    const DenseDepth d = estimator.estimate(f.image, f.priors);
    ASSERT_TRUE(d.pose.valid()) << d.pose.reason;
    // S1 is piecewise constant around the priors, so the plane through it is close, not exact.
    EXPECT_NEAR(d.pose.psi_net_rad, f.scene.psi_rad, 0.03);
    EXPECT_NEAR(d.pose.pitch_net_rad, f.scene.pitch_rad, 0.03);
    // The central window's mean depth against the plane's depth on the axis.
    EXPECT_NEAR(d.pose.d_net_m, f.scene.distance_m, 0.03 * f.scene.distance_m);
  }
}

// A 4:3 network on a 16:9 camera runs on the camera's centred 4:3 crop: depth there, NaN on the
// sides, and the plane from it as on a 4:3 camera.
TEST_F(DepthEstimatorTest, AnotherAspectRunsOnTheCentredCrop) {
  PinholeCamera cam;
  cam.width_px = 960;
  cam.cx_px = 479.5;
  DepthEstimator estimator(cam,
                           {.model = s1_model(320, 240),
                            .backend = Backend::kCpu,
                            .cpu_inference = CpuInference::kEngine},
                           testing::test_device());
  const Frame f = plane_frame(cam, testing::fresh_seed());
  ASSERT_FALSE(f.priors.empty());
  const DenseDepth d = estimator.estimate(f.image, f.priors);
  ASSERT_TRUE(d.reason.empty()) << d.reason;
  ASSERT_EQ(d.depth_m.width, 960);
  for (const int y : {0, 269, 539}) {
    EXPECT_TRUE(std::isnan(d.depth_m.at(0, y)));
    EXPECT_TRUE(std::isnan(d.depth_m.at(119, y)));
    EXPECT_TRUE(std::isfinite(d.depth_m.at(120, y)));
    EXPECT_TRUE(std::isfinite(d.depth_m.at(839, y)));
    EXPECT_TRUE(std::isnan(d.depth_m.at(840, y)));
  }
  ASSERT_TRUE(d.pose.valid()) << d.pose.reason;
  EXPECT_NEAR(d.pose.psi_net_rad, f.scene.psi_rad, 0.03);
  EXPECT_NEAR(d.pose.pitch_net_rad, f.scene.pitch_rad, 0.03);
  EXPECT_NEAR(d.pose.d_net_m, f.scene.distance_m, 0.03 * f.scene.distance_m);
}

// A network whose scale is off by a common factor is pinned to the priors: twice S1 comes out as
// S1.
TEST_F(DepthEstimatorTest, ScaleIsAlignedToThePriors) {
  const PinholeCamera cam;
  const Frame f = plane_frame(cam, testing::fresh_seed());
  ASSERT_FALSE(f.priors.empty());
  testing::write_s1_depth_model(dir_ / "s1x2.onnx", 320, 240, 2.0f);
  DepthEstimator doubled(cam,
                         {.model = dir_ / "s1x2.onnx",
                          .backend = Backend::kCpu,
                          .cpu_inference = CpuInference::kEngine},
                         testing::test_device());
  DepthEstimator plain(cam,
                       {.model = s1_model(320, 240),
                        .backend = Backend::kCpu,
                        .cpu_inference = CpuInference::kEngine},
                       testing::test_device());
  const DenseDepth a = doubled.estimate(f.image, f.priors), b = plain.estimate(f.image, f.priors);
  ASSERT_EQ(a.depth_m.pixels.size(), b.depth_m.pixels.size());
  for (size_t i = 0; i < a.depth_m.pixels.size(); i += 101) {
    ASSERT_NEAR(a.depth_m.pixels[i], b.depth_m.pixels[i], 1e-5f * b.depth_m.pixels[i]) << i;
  }
}

TEST_F(DepthEstimatorTest, BadModelsSizesAndFramesWithoutPriors) {
  const PinholeCamera cam;
  try {
    DepthEstimator(cam, {.model = dir_ / "missing.onnx"}, testing::test_device());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.onnx"), std::string::npos) << e.what();
  }
  // TRUDepth's RGB image input is not this stage's contract.
  const fs::path rgb = write(
      kernels::trudepth_net({64, 48}, 0.25f, 1, kernels::DepthHead::kConvSoftplus), "rgb.onnx");
  try {
    DepthEstimator(cam, {.model = rgb}, testing::test_device());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a depth network"), std::string::npos) << e.what();
  }
  std::ofstream(dir_ / "junk.onnx") << "not a protobuf";
  EXPECT_THROW(DepthEstimator(cam, {.model = dir_ / "junk.onnx"}, testing::test_device()), Error);

  DepthEstimator estimator(
      cam,
      {.model = s1_model(64, 48), .backend = Backend::kCpu, .cpu_inference = CpuInference::kEngine},
      testing::test_device());
  EXPECT_THROW(estimator.estimate(ImageU8(640, 480), {}), Error);
  const DenseDepth none = estimator.estimate(ImageU8(cam.width_px, cam.height_px), {});
  EXPECT_FALSE(none.reason.empty());
  EXPECT_TRUE(none.depth_m.empty());
  EXPECT_TRUE(std::isnan(none.pose.d_net_m));
  const std::vector<SparseDepth> nan_prior = {{{100, 100, std::nanf("")}, 1}};
  EXPECT_THROW(estimator.estimate(ImageU8(cam.width_px, cam.height_px), nan_prior), Error);
  EXPECT_THROW(parse_cpu_inference("tensorrt"), Error);
  // No CUDA path for the network: asked for, it is refused with the alternatives.
  EXPECT_THROW(DepthEstimator(cam, {.model = s1_model(64, 48), .backend = Backend::kCuda},
                              testing::test_device()),
               Error);
}

}  // namespace
}  // namespace pensight
