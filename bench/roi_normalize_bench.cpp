// ROI extraction + normalisation for the default FFT grid (30 ROIs of 300 px from 720x540 u8):
// CPU reference vs Vulkan, in one run. Floor: each ROI is read 3 times (mean, variance, write)
// from cache-resident data, and 30*300*300*4 = 10.8 MB of floats are written.
#include <benchmark/benchmark.h>

#include <random>

#include "kernels/roi_normalize/roi_normalize.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"

namespace {

using namespace pensight;

constexpr kernels::RoiNormalizeShape kShape{720, 540, 8, 300};

ImageU8 frame() {
  ImageU8 img(kShape.width, kShape.height);
  std::mt19937 rng(1);
  for (auto& p : img.pixels) p = static_cast<uint8_t>(rng());
  return img;
}

std::vector<kernels::RoiOrigin> grid() {
  std::vector<kernels::RoiOrigin> rois;
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 6; ++c) rois.push_back({c * (720 - 300) / 5, r * (540 - 300) / 4});
  return rois;
}

void set_counters(benchmark::State& state, size_t rois) {
  const double out_bytes = static_cast<double>(rois) * 300 * 300 * sizeof(float);
  state.SetBytesProcessed(
      static_cast<int64_t>(static_cast<double>(state.iterations()) * (out_bytes + 720.0 * 540)));
  state.counters["rois"] = static_cast<double>(rois);
}

void BM_RoiNormalize_Cpu(benchmark::State& state) {
  const ImageU8 img = frame();
  const auto rois = grid();
  std::vector<float> out(rois.size() * 300 * 300);
  for (auto _ : state) {
    kernels::roi_normalize_cpu(img, rois, 300, out);
    benchmark::DoNotOptimize(out.data());
  }
  set_counters(state, rois.size());
}
BENCHMARK(BM_RoiNormalize_Cpu)->Unit(benchmark::kMillisecond);

// Per frame: upload the image, run the recorded stream, results stay on the device.
void BM_RoiNormalize_Vulkan(benchmark::State& state) {
  const vk::Context ctx;
  state.SetLabel(ctx.info().name);
  const ImageU8 img = frame();
  const auto rois = grid();
  const kernels::RoiNormalizeVk kernel(ctx, kShape);
  vk::Buffer image(ctx, kernel.image_bytes());
  vk::Buffer origins(ctx, rois.size() * sizeof(kernels::RoiOrigin));
  origins.upload(rois.data(), rois.size() * sizeof(kernels::RoiOrigin));
  vk::Buffer out(ctx, rois.size() * 300 * 300 * sizeof(float));
  vk::CommandStream stream(ctx);
  kernel.record(stream, image, origins, out, static_cast<uint32_t>(rois.size()));
  double device_ms = 0;
  for (auto _ : state) {
    image.upload(img.pixels.data(), img.pixels.size());
    stream.submit_and_wait();
    if (!stream.timings().empty()) device_ms += stream.timings()[0].device_ms;
  }
  state.counters["device_ms"] = device_ms / static_cast<double>(state.iterations());
  set_counters(state, rois.size());
}
BENCHMARK(BM_RoiNormalize_Vulkan)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
