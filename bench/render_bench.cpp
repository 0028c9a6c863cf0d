// Synthetic camera frames at 720x540 (scenarios/follow.yaml, the net at 0.5 m filling the view):
// the CPU reference vs the Vulkan renderer, per frame, at 1 and 2x2 samples per pixel. Floor:
// per sample one ray-cylinder and one ray-plane test plus ~10 transcendental calls for shading;
// 720*540*4 = 1.56 M samples per frame at 2x2.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "bench/process_cpu.h"
#include "runtime/vk_context.h"
#include "sim/frame_state.h"
#include "sim/render_cpu.h"
#include "sim/render_vk.h"
#include "sim/scenario.h"

namespace {

using namespace pensight;
using bench::process_cpu_s;

void set_counters(benchmark::State& state, double cpu_s) {
  const auto n = static_cast<double>(state.iterations());
  state.counters["fps"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["cpu_ms_per_frame"] = 1e3 * cpu_s / n;
}

sim::Scenario scenario(int samples) {
  const char* root = std::getenv("PENSIGHT_SOURCE_DIR");
  sim::Scenario s =
      sim::load_scenario(std::string(root ? root : PENSIGHT_SOURCE_DIR) + "/scenarios/follow.yaml");
  s.camera.samples_per_axis = samples;
  return s;
}

void BM_Render_Cpu(benchmark::State& state) {
  const sim::Scenario s = scenario(static_cast<int>(state.range(0)));
  const sim::NetGeometry net(s.pen, s.net);
  const sim::FrameState f = sim::frame_state(s, 0);
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    auto r = sim::render_cpu(s, net, f);
    benchmark::DoNotOptimize(r.image.pixels.data());
  }
  set_counters(state, process_cpu_s() - cpu0);
}
BENCHMARK(BM_Render_Cpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Device time of the dispatch only (no upload/download): what a closed loop that keeps the frame
// on the device pays.
void BM_Render_Vulkan(benchmark::State& state) {
  static const vk::Context ctx;
  const sim::Scenario s = scenario(static_cast<int>(state.range(0)));
  sim::RenderOptions o;
  o.noise = state.range(1) & 1;
  o.marine_snow = state.range(1) & 2;
  const sim::RenderVk vk_render(ctx, s, o);
  const size_t pixels = 720 * 540;
  const auto data = vk_render.frame_data(sim::frame_state(s, 0));
  vk::Buffer frame(ctx, data.frame.size()), tiles(ctx, data.tiles.size() * sizeof(uint32_t));
  frame.upload(data.frame.data(), data.frame.size());
  tiles.upload(data.tiles.data(), data.tiles.size() * sizeof(uint32_t));
  vk::TypedBuffer<float> image(ctx, pixels), depth(ctx, pixels);
  vk::CommandStream stream(ctx);
  vk_render.record(stream, frame, tiles, image.raw(), depth.raw());
  stream.submit_and_wait();  // warm-up
  const double cpu0 = process_cpu_s();
  for (auto _ : state) stream.submit_and_wait();
  set_counters(state, process_cpu_s() - cpu0);
  state.SetLabel(ctx.info().name);
}
BENCHMARK(BM_Render_Vulkan)
    ->Args({1, 3})
    ->Args({2, 3})
    ->Args({1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
