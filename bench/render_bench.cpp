// Synthetic camera frames at 720x540 (scenarios/follow.yaml, the net at 0.5 m filling the view):
// the CPU reference vs the Vulkan renderer, per frame, at 1 and 2x2 samples per pixel. Floor:
// per sample one ray-cylinder and one ray-plane test plus ~10 transcendental calls for shading;
// 720*540*4 = 1.56 M samples per frame at 2x2.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "runtime/vk_context.h"
#include "sim/frame_state.h"
#include "sim/render_cpu.h"
#include "sim/render_vk.h"
#include "sim/scenario.h"

namespace {

using namespace pensight;

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
  for (auto _ : state) {
    auto r = sim::render_cpu(s, net, f);
    benchmark::DoNotOptimize(r.image.pixels.data());
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
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
  vk::Buffer params(ctx, sim::RenderVk::params_bytes());
  vk::TypedBuffer<float> image(ctx, pixels), depth(ctx, pixels);
  const auto bytes = vk_render.params(sim::frame_state(s, 0));
  params.upload(bytes.data(), bytes.size());
  vk::CommandStream stream(ctx);
  vk_render.record(stream, params, image.raw(), depth.raw());
  stream.submit_and_wait();  // warm-up
  for (auto _ : state) stream.submit_and_wait();
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(ctx.info().name);
}
BENCHMARK(BM_Render_Vulkan)
    ->Args({1, 3})
    ->Args({2, 3})
    ->Args({1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
