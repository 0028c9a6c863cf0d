// Pipeline overhead per frame: one frame pushed and its result awaited, against the same stages
// called directly on the calling thread. The stages are kept tiny (a 160x120 camera, one 64 px ROI
// resampled to 32) so the difference, three thread hand-offs and the queues, is what is measured.
#include <benchmark/benchmark.h>

#include <condition_variable>
#include <mutex>

#include "pipeline/pipeline.h"

namespace pensight {
namespace {

PipelineConfig tiny_config() {
  PipelineConfig c;
  c.camera = {
      .width_px = 160, .height_px = 120, .fx_px = 100, .fy_px = 100, .cx_px = 79.5, .cy_px = 59.5};
  c.detector.grid = {.rows = 1, .cols = 1, .roi_size_px = 64, .border_px = 0};
  c.detector.fft_size = 32;
  c.detector.backend = Backend::kCpu;
  c.detector.cpu_threads = 1;
  c.global_pose.pen_radius_m = 12;
  return c;
}

ImageU8 tiny_frame() {
  ImageU8 img(160, 120);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) = static_cast<uint8_t>((x * 7 + y * 3) % 251);
  return img;
}

void BM_DirectCalls(benchmark::State& state) {
  const PipelineConfig c = tiny_config();
  Device device;
  NetDetector detector(c.camera, c.detector, device);
  global_pose::GlobalPoseEstimator est(c.global_pose);
  const ImageU8 img = tiny_frame();
  int64_t t = 0;
  for (auto _ : state) {
    t += 100'000'000;
    const NetDetection d = detector.detect(img, t);
    global_pose::NetObservation obs;
    obs.t_ns = t;
    for (const RoiNetPoint& p : d.points) {
      obs.points_C.push_back(p.p_C);
      obs.quality.push_back(1.0);
    }
    est.add(obs);
    benchmark::DoNotOptimize(est.estimate(t));
  }
}
BENCHMARK(BM_DirectCalls)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_PipelineRoundTrip(benchmark::State& state) {
  PipelineConfig c = tiny_config();
  std::mutex mutex;
  std::condition_variable cv;
  int64_t last = 0;
  c.on_frame = [&](const FrameResult& r) {
    std::lock_guard lock(mutex);
    last = r.timestamp_ns;
    cv.notify_one();
  };
  Device device;
  Pipeline p(c, device);
  const ImageU8 img = tiny_frame();
  int64_t t = 0;
  for (auto _ : state) {
    t += 100'000'000;
    p.push(CameraFrame{t, img});
    std::unique_lock lock(mutex);
    cv.wait(lock, [&] { return last == t; });
  }
  p.finish();
}
BENCHMARK(BM_PipelineRoundTrip)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace pensight
