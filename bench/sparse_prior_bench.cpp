// S1/S2 prior maps at the network input sizes (320x240, 720x540) with 30 and 300 sparse points:
// our exact CPU path, the Vulkan kernel, and cv::distanceTransform (DIST_L2, 5x5 mask,
// DIST_LABEL_PIXEL: approximate labels, and it gives the nearest seed only, not S1/S2 yet - the
// label-to-depth lookup and exp() are added so the work compares). Floor: 2 planes of W*H floats
// written (0.6 MB at 320x240, 3.1 MB at 720x540).
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "kernels/sparse_prior/sparse_prior.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"

namespace {

using namespace pensight;
using kernels::SparsePoint;

std::vector<SparsePoint> points(int w, int h, int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(0, static_cast<float>(w - 1)),
      uy(0, static_cast<float>(h - 1)), ud(1, 5);
  std::vector<SparsePoint> p(static_cast<size_t>(n));
  for (auto& q : p) q = {ux(rng), uy(rng), ud(rng)};
  return p;
}

void counters(benchmark::State& state, int w, int h) {
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * 2 * w * h * 4);
}

void BM_SparsePrior_CpuExact(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto pts = points(w, h, static_cast<int>(state.range(2)));
  std::vector<float> out(2 * static_cast<size_t>(w) * h);
  for (auto _ : state) {
    kernels::sparse_prior_cpu({w, h, 10}, pts, out);
    benchmark::DoNotOptimize(out.data());
  }
  counters(state, w, h);
}

void BM_SparsePrior_Vulkan(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto pts = points(w, h, static_cast<int>(state.range(2)));
  const vk::Context ctx;
  state.SetLabel(ctx.info().name);
  const kernels::SparsePriorVk kernel(ctx, {w, h, 10});
  vk::Buffer point_buf(ctx, pts.size() * sizeof(SparsePoint));
  vk::TypedBuffer<kernels::SparsePriorParams> params(ctx, 1);
  vk::Buffer out(ctx, 2 * static_cast<size_t>(w) * h * sizeof(float));
  vk::CommandStream stream(ctx);
  kernel.record(stream, point_buf, params, out);
  double device_ms = 0;
  for (auto _ : state) {
    // A frame's work: its points and their count, then the stream recorded once.
    point_buf.upload(pts.data(), pts.size() * sizeof(SparsePoint));
    params.fill({static_cast<uint32_t>(pts.size())});
    stream.submit_and_wait();
    if (!stream.timings().empty()) device_ms += stream.timings()[0].device_ms;
  }
  state.counters["device_ms"] = device_ms / static_cast<double>(state.iterations());
  counters(state, w, h);
}

void BM_SparsePrior_OpenCvDistanceTransform(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto pts = points(w, h, static_cast<int>(state.range(2)));
  cv::Mat seeds(h, w, CV_8U), dist, labels;
  cv::Mat s1(h, w, CV_32F), s2(h, w, CV_32F);
  std::vector<float> depth_of_label;
  for (auto _ : state) {
    seeds.setTo(1);
    for (const auto& p : pts) seeds.at<uint8_t>(int(p.y_px + 0.5f), int(p.x_px + 0.5f)) = 0;
    cv::distanceTransform(seeds, dist, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
    depth_of_label.assign(pts.size() + 1, 0.f);
    for (const auto& p : pts) {
      depth_of_label[static_cast<size_t>(labels.at<int>(int(p.y_px + 0.5f), int(p.x_px + 0.5f)))] =
          p.depth_m;
    }
    for (int y = 0; y < h; ++y) {
      const int* l = labels.ptr<int>(y);
      const float* d = dist.ptr<float>(y);
      float* a = s1.ptr<float>(y);
      float* b = s2.ptr<float>(y);
      for (int x = 0; x < w; ++x) {
        a[x] = depth_of_label[static_cast<size_t>(l[x])];
        b[x] = std::exp(-d[x] * d[x] * 0.005f);
      }
    }
    benchmark::DoNotOptimize(s2.data);
  }
  counters(state, w, h);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (const auto& wh : {std::pair{320, 240}, std::pair{720, 540}}) {
    for (int n : {30, 300}) b->Args({wh.first, wh.second, n});
  }
  b->ArgNames({"w", "h", "points"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_SparsePrior_CpuExact)->Apply(sizes);
BENCHMARK(BM_SparsePrior_Vulkan)->Apply(sizes);
BENCHMARK(BM_SparsePrior_OpenCvDistanceTransform)->Apply(sizes);

}  // namespace
