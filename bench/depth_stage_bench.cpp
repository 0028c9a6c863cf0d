// The dense-depth stage per frame on the shipped model (models/compact_depth.onnx) at 320x240:
// area resize, priors -> S1/S2 and Q, network, alignment to the priors, bilinear resize to 720x540
// and the pose (DepthEstimator::estimate; the counter network_ms leaves the pose out) on each
// backend side by side: OpenCV DNN, the engine's CPU executor, the engine's Vulkan executor
// (lavapipe on a machine without a GPU; S1/S2 on the device). ONNX Runtime CPU as the peer: node
// bench/ort_bench.js models/compact_depth.onnx 20 image=1x1x240x320 prior=1x3x240x320. Then the
// pose from dense depth (every pixel, IRLS), and the DVL's scale and tilt of it. Counters: GFLOP
// per frame and achieved GFLOP/s. The frame: follow.yaml's first, rendered.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>
#include <utility>

#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/dvl_depth_scale.h"
#include "pipeline/depth/dvl_net_tilt.h"
#include "pipeline/fft/net_detector.h"
#include "runtime/device.h"
#include "sim/frame_state.h"
#include "sim/net_geometry.h"
#include "sim/render_cpu.h"
#include "sim/scenario.h"
#include "sim/sensors.h"

namespace {

using namespace pensight;

const std::filesystem::path kModel =
    std::filesystem::path(PENSIGHT_SOURCE_DIR) / "models/compact_depth.onnx";

struct Frame {
  PinholeCamera camera;
  ImageU8 image;
  std::vector<SparseDepth> priors;
};

const Frame& frame() {
  static const Frame f = [] {
    const sim::Scenario s =
        sim::load_scenario(std::filesystem::path(PENSIGHT_SOURCE_DIR) / "scenarios/follow.yaml");
    const sim::NetGeometry net(s.pen, s.net);
    Frame out;
    out.camera = s.camera.calibration.camera;
    out.image = sim::render_cpu(s, net, sim::frame_state(s, 0)).image;
    Device device;
    NetDetectorConfig config;
    config.backend = Backend::kCpu;
    config.bar_length_m = s.net.bar_length_m;
    out.priors = NetDetector(out.camera, config, device).detect(out.image).depths;
    return out;
  }();
  return f;
}

// range(0): 0 OpenCV DNN, 1 engine CPU, 2 engine Vulkan.
void BM_DepthStage(benchmark::State& state) {
  if (!std::filesystem::exists(kModel)) {
    state.SkipWithError("no models/compact_depth.onnx (scripts/train_depth.sh)");
    return;
  }
  const std::pair<Backend, CpuInference> backends[] = {{Backend::kCpu, CpuInference::kOpenCv},
                                                       {Backend::kCpu, CpuInference::kEngine},
                                                       {Backend::kVulkan, CpuInference::kAuto}};
  const Frame& f = frame();
  Device device;
  std::optional<DepthEstimator> estimator;
  try {
    estimator.emplace(f.camera,
                      DepthEstimatorConfig{.model = kModel,
                                           .backend = backends[state.range(0)].first,
                                           .cpu_inference = backends[state.range(0)].second},
                      device);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  double network_ms = 0;
  for (auto _ : state) {
    const DenseDepth d = estimator->estimate(f.image, f.priors);
    network_ms += d.network_ms;
    benchmark::DoNotOptimize(d.depth_m.pixels.data());
  }
  const double gflop = estimator->gflop();
  state.counters["GFLOP"] = gflop;
  state.counters["GFLOP/s"] = benchmark::Counter(gflop * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  state.counters["network_ms"] =
      network_ms / static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
  state.SetLabel(to_string(estimator->backend()));
}
BENCHMARK(BM_DepthStage)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DepthPlanePose(benchmark::State& state) {
  const PinholeCamera cam = frame().camera.scaled(320.0 / 720);
  const PixelRays rays(cam);
  ImageF32 depth(cam.width_px, cam.height_px);
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const Eigen::Vector3d r = cam.ray({u, v});
      depth.at(u, v) = static_cast<float>(0.8 / (1 - 0.3 * r.x() - 0.1 * r.y()));
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(depth_plane_pose(depth, rays).psi_net_rad);
}
BENCHMARK(BM_DepthPlanePose)->Unit(benchmark::kMillisecond)->UseRealTime();

// A 4 Hz DVL beside 10 Hz frames: the sample the frame at t_ns is the first after (DVL samples at
// 0 and 250 ms of every half second meet the frames at 0 and 300 ms).
std::optional<int64_t> dvl_sample_time(int64_t t_ns) {
  if (t_ns % 500'000'000 == 0) return t_ns;
  if (t_ns % 500'000'000 == 300'000'000) return t_ns - 50'000'000;
  return std::nullopt;
}

// The DVL's scale of dense depth per frame at 720x540 (dvl_depth_scale.h): a 4 Hz DVL paired
// with 10 Hz frames (0.4 samples a frame, four beam spots each) over a full 10 s window; then the
// copy that applies an engaged scale.
void BM_DvlDepthScale(benchmark::State& state) {
  const PinholeCamera cam = frame().camera;
  const ImageF32 depth(cam.width_px, cam.height_px, 1.0f);
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();
  T_body_camera.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  const DvlCalibration dvl = sim::dvl_calibration(sim::DvlConfig{});
  DvlDepthScale scale(cam, T_body_camera, dvl);
  DvlSample s;
  s.valid = true;
  s.beam_range_m = {1.1, 1.1, 1.1, 1.1};
  int64_t t_ns = 0;
  for (auto _ : state) {
    t_ns += 100'000'000;
    if (const auto t_dvl = dvl_sample_time(t_ns)) {
      s.timestamp_ns = *t_dvl;
      scale.add(s);
    }
    benchmark::DoNotOptimize(scale.update(t_ns, depth).scale);
  }
  state.counters["window"] = scale.state().samples;
}
BENCHMARK(BM_DvlDepthScale)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_ScaledDepth(benchmark::State& state) {
  const PinholeCamera cam = frame().camera;
  const ImageF32 depth(cam.width_px, cam.height_px, 1.0f);
  for (auto _ : state) benchmark::DoNotOptimize(scaled_depth(depth, 1.03).pixels.data());
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(depth.pixels.size()) * 8);
}
BENCHMARK(BM_ScaledDepth)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The DVL's tilt per frame with a full 1.5 s window (a plane fit per new sample); then the pass
// that turns an engaged frame's 720x540 depth.
void BM_DvlNetTilt(benchmark::State& state) {
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();
  T_body_camera.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  const DvlCalibration dvl = sim::dvl_calibration(sim::DvlConfig{});
  DvlNetTilt tilt(T_body_camera, dvl);
  DvlSample s;
  s.valid = true;
  s.beam_range_m = {1.1, 1.12, 1.1, 1.12};
  DepthPlanePose pose;
  pose.d_net_m = 1;
  pose.psi_net_rad = pose.pitch_net_rad = 0;
  pose.reason.clear();
  int64_t t_ns = 0;
  for (auto _ : state) {
    t_ns += 100'000'000;
    if (const auto t_dvl = dvl_sample_time(t_ns)) {
      s.timestamp_ns = *t_dvl;
      tilt.add(s);
    }
    benchmark::DoNotOptimize(tilt.update(t_ns, pose).psi_diff_rad);
  }
  state.counters["window"] = tilt.state().samples;
}
BENCHMARK(BM_DvlNetTilt)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_TiltedDepth(benchmark::State& state) {
  const PinholeCamera cam = frame().camera;
  const PixelRays rays(cam);
  const ImageF32 depth(cam.width_px, cam.height_px, 1.0f);
  DepthPlanePose pose;
  pose.d_net_m = 1;
  pose.psi_net_rad = 0.3;
  pose.pitch_net_rad = 0.05;
  pose.reason.clear();
  for (auto _ : state) {
    benchmark::DoNotOptimize(tilted_depth(depth, rays, pose, 0.05, 0).pixels.data());
  }
  // The depth read and written, the rays read.
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(depth.pixels.size()) * 16);
}
BENCHMARK(BM_TiltedDepth)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
