// The nn engine on the compact depth-completion net and the TRUDepth-architecture graph (width
// 0.5) at 320x240: Vulkan executor, CPU reference executor, OpenCV DNN (not on the AdaBins head:
// OpenCV 4.6 cannot import LayerNormalization). ONNX Runtime CPU: bench/ort_bench.js on the
// exported files (pensight export-onnx builtin:compact / builtin:trudepth). Counters: GFLOP per
// inference (conv/matmul multiply-adds x 2) and achieved GFLOP/s.
#include <benchmark/benchmark.h>

#include <opencv2/dnn.hpp>
#include <random>

#include "kernels/nn/nn.h"
#include "kernels/nn/nn_models.h"
#include "kernels/nn/nn_onnx.h"
#include "runtime/vk_context.h"

namespace {

using namespace pensight;

// 0: compact net, 1: TRUDepth-0.5, 2: TRUDepth-0.5 encoder-decoder without the AdaBins head (the
// part OpenCV DNN can run).
kernels::Graph model(int which) {
  if (which == 0) return kernels::compact_depth_net({320, 240}, 1);
  return kernels::trudepth_net(
      {320, 240}, 0.5f, 1,
      which == 1 ? kernels::DepthHead::kAdaBins : kernels::DepthHead::kConvSoftplus);
}
const char* model_name(int64_t which) {
  return which == 0 ? "compact" : which == 1 ? "trudepth-0.5" : "trudepth-0.5-no-head";
}

std::vector<kernels::Tensor> inputs(const kernels::Graph& g) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<kernels::Tensor> in;
  for (int v : g.inputs()) {
    kernels::Tensor t{
        g.value(v).shape,
        std::vector<float>(static_cast<size_t>(kernels::num_elements(g.value(v).shape)))};
    for (float& x : t.data) x = u(rng);
    in.push_back(std::move(t));
  }
  return in;
}

void counters(benchmark::State& state, const kernels::Graph& g) {
  state.counters["GFLOP"] = g.flops() * 1e-9;
  state.counters["GFLOP/s"] = benchmark::Counter(
      g.flops() * 1e-9 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(model_name(state.range(0)));
}

// range(1) = 1: fp16 storage (skipped where the device lacks it).
void BM_Nn_Vulkan(benchmark::State& state) {
  const kernels::Graph g = model(static_cast<int>(state.range(0)));
  const auto in = inputs(g);
  const vk::Context ctx;
  const bool fp16 = state.range(1) == 1;
  if (fp16 && !ctx.info().fp16_storage) {
    state.SkipWithError("no 16-bit storage on this device");
    return;
  }
  kernels::VkModel m(ctx, g, {.fp16_storage = fp16});
  for (size_t i = 0; i < in.size(); ++i)
    m.input_buffer(i).upload(in[i].data.data(), in[i].data.size() * 4);
  for (auto _ : state) m.submit();
  counters(state, g);
  state.counters["dispatches"] = static_cast<double>(m.num_dispatches());
  state.counters["act_MB"] = static_cast<double>(m.activation_bytes()) / 1e6;
  state.counters["unplanned_MB"] = static_cast<double>(m.unplanned_activation_bytes()) / 1e6;
}
BENCHMARK(BM_Nn_Vulkan)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->ArgNames({"model", "fp16"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Nn_CpuReference(benchmark::State& state) {
  const kernels::Graph g = model(static_cast<int>(state.range(0)));
  const auto in = inputs(g);
  for (auto _ : state) benchmark::DoNotOptimize(kernels::run_cpu(g, in));
  counters(state, g);
}
BENCHMARK(BM_Nn_CpuReference)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Nn_OpenCvDnn(benchmark::State& state) {
  const kernels::Graph g = model(static_cast<int>(state.range(0)));
  const auto in = inputs(g);
  const std::string bytes = kernels::opencv_dnn_compatible(kernels::export_onnx_bytes(g));
  cv::dnn::Net net = cv::dnn::readNetFromONNX(bytes.data(), bytes.size());
  for (size_t i = 0; i < in.size(); ++i) {
    std::vector<int> dims(in[i].shape.begin(), in[i].shape.end());
    net.setInput(cv::Mat(4, dims.data(), CV_32F, const_cast<float*>(in[i].data.data())),
                 g.value(g.inputs()[i]).name);
  }
  for (auto _ : state) benchmark::DoNotOptimize(net.forward());
  counters(state, g);
}
BENCHMARK(BM_Nn_OpenCvDnn)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
