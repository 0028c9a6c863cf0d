// ONNX export/import and independent checks: the ONNX checker, OpenCV DNN and ONNX Runtime
// (through its Node.js package) must reproduce our outputs from the exported file.
#include <gtest/gtest.h>
#include <onnx/onnx_pb.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <opencv2/dnn.hpp>
#include <optional>

#include "core/error.h"
#include "core/file_bytes.h"
#include "kernels/nn/nn.h"
#include "kernels/nn/nn_models.h"
#include "kernels/nn/nn_onnx.h"
#include "tests/kernels/nn/nn_test_util.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::kernels {
namespace {

namespace fs = std::filesystem;
using testing::VulkanTest;
using testutil::random_tensor;
using testutil::relative_l2;

std::vector<Tensor> random_inputs(const Graph& g, std::mt19937_64& rng) {
  std::vector<Tensor> in;
  for (int v : g.inputs()) in.push_back(random_tensor(g.value(v).shape, rng, 0.f, 1.f));
  return in;
}

std::vector<Tensor> run_opencv(const std::string& onnx_bytes, const Graph& g,
                               const std::vector<Tensor>& inputs) {
  const std::string bytes = opencv_dnn_compatible(onnx_bytes);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(bytes.data(), bytes.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    std::vector<int> dims(inputs[i].shape.begin(), inputs[i].shape.end());
    cv::Mat m(static_cast<int>(dims.size()), dims.data(), CV_32F,
              const_cast<float*>(inputs[i].data.data()));
    net.setInput(m, g.value(g.inputs()[i]).name);
  }
  std::vector<std::string> names;
  for (int v : g.outputs()) names.push_back(g.value(v).name);
  std::vector<cv::Mat> outs;
  net.forward(outs, names);
  std::vector<Tensor> result;
  for (size_t i = 0; i < outs.size(); ++i) {
    const cv::Mat m = outs[i].isContinuous() ? outs[i] : outs[i].clone();
    result.push_back({g.value(g.outputs()[i]).shape,
                      std::vector<float>(m.ptr<float>(), m.ptr<float>() + m.total())});
  }
  return result;
}

// The folder holding node_modules/onnxruntime-node, or empty (test skipped).
fs::path ort_dir() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("PENSIGHT_ORT_NODE_DIR")) candidates.emplace_back(env);
  if (const char* src = std::getenv("PENSIGHT_SOURCE_DIR"))
    candidates.push_back(fs::path(src) / ".cache" / "ort");
  for (const auto& c : candidates) {
    if (fs::exists(c / "node_modules" / "onnxruntime-node")) return c;
  }
  return {};
}

std::vector<Tensor> run_ort(const fs::path& dir, const std::string& bytes, const Graph& g,
                            const std::vector<Tensor>& inputs) {
  const fs::path work = fs::temp_directory_path() / ("pensight_ort_" + std::to_string(::getpid()));
  fs::create_directories(work);
  std::ofstream(work / "model.onnx", std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const char* src = std::getenv("PENSIGHT_SOURCE_DIR");
  std::string cmd = "NODE_PATH='" + (dir / "node_modules").string() + "' node '" +
                    std::string(src) + "/tests/kernels/nn/ort_run.js' '" +
                    (work / "model.onnx").string() + "' '" + work.string() + "'";
  for (size_t i = 0; i < inputs.size(); ++i) {
    const fs::path f = work / ("in" + std::to_string(i) + ".bin");
    std::ofstream(f, std::ios::binary)
        .write(reinterpret_cast<const char*>(inputs[i].data.data()),
               static_cast<std::streamsize>(inputs[i].data.size() * 4));
    std::string dims;
    for (int64_t d : inputs[i].shape) dims += (dims.empty() ? "" : "x") + std::to_string(d);
    cmd += " '" + g.value(g.inputs()[i]).name + "=" + f.string() + "=" + dims + "'";
  }
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::vector<Tensor> out;
  for (size_t i = 0; i < g.outputs().size(); ++i) {
    const Dims& s = g.value(g.outputs()[i]).shape;
    Tensor t{s, std::vector<float>(static_cast<size_t>(num_elements(s)))};
    std::ifstream(work / (std::to_string(i) + ".bin"), std::ios::binary)
        .read(reinterpret_cast<char*>(t.data.data()),
              static_cast<std::streamsize>(t.data.size() * 4));
    out.push_back(std::move(t));
  }
  fs::remove_all(work);
  return out;
}

// Export, check, re-import; CPU reference of the re-imported graph, Vulkan and OpenCV DNN all
// against the CPU reference of the original graph. Vulkan fp32 is held to fp32_bound (its sums
// run in another order), fp16 storage to fp16_bound.
void check_model(const vk::Context& ctx, const Graph& g, uint64_t seed, double fp16_bound = 2e-2,
                 double fp32_bound = 1e-5) {
  std::mt19937_64 rng(seed);
  const auto inputs = random_inputs(g, rng);
  const auto want = run_cpu(g, inputs);
  const std::string bytes = export_onnx_bytes(g);
  ASSERT_NO_THROW(check_onnx_bytes(bytes));
  const Graph back = import_onnx_bytes(bytes);
  const auto again = run_cpu(back, inputs);
  VkModel model(ctx, back);
  model.fill_activations(pensight::testing::kPoison);
  const auto vk_out = model.run(inputs);
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_LT(relative_l2(again[i], want[i]), 1e-6);
    const double e = relative_l2(vk_out[i], want[i]);
    std::printf("Vulkan fp32 vs fp32 reference: relative L2 %.2e\n", e);
    EXPECT_LT(e, fp32_bound);
  }
  if (ctx.info().fp16_storage) {
    VkModel half(ctx, back, {.fp16_storage = true});
    half.fill_activations(pensight::testing::kPoison);
    const double e = relative_l2(half.run(inputs)[0], want[0]);
    std::printf("Vulkan fp16 storage vs fp32 reference: relative L2 %.2e\n", e);
    EXPECT_LT(e, fp16_bound);
  }
  // OpenCV 4.6 (Debian 12) has no LayerNormalization layer: those graphs are checked by ONNX
  // Runtime only.
  const bool has_layer_norm = std::any_of(g.nodes().begin(), g.nodes().end(),
                                          [](const Node& n) { return n.op == Op::kLayerNorm; });
  if (has_layer_norm)
    std::printf("OpenCV DNN check skipped: OpenCV 4.6 cannot import LayerNormalization\n");
  if (!has_layer_norm) {
    const auto cv_out = run_opencv(bytes, g, inputs);
    for (size_t i = 0; i < want.size(); ++i) {
      const double e = relative_l2(cv_out[i], want[i]);
      std::printf("OpenCV DNN vs ours: relative L2 %.2e\n", e);
      EXPECT_LT(e, 1e-4);
    }
  }
  const fs::path dir = ort_dir();
  if (dir.empty()) {
    std::printf(
        "ONNX Runtime check skipped: no node_modules/onnxruntime-node (run `npm install "
        "onnxruntime-node "
        "--ignore-scripts` in .cache/ort or set PENSIGHT_ORT_NODE_DIR)\n");
    return;
  }
  const auto ort_out = run_ort(dir, bytes, g, inputs);
  for (size_t i = 0; i < want.size(); ++i) {
    const double e = relative_l2(ort_out[i], want[i]);
    std::printf("ONNX Runtime vs ours: relative L2 %.2e\n", e);
    EXPECT_LT(e, 1e-4);
  }
}

TEST_F(VulkanTest, OnnxAllOpsGraph) {
  const uint64_t seed = pensight::testing::fresh_seed();
  check_model(ctx(), all_ops_net(seed), seed);
}

TEST_F(VulkanTest, OnnxCompactDepthNet) {
  const uint64_t seed = pensight::testing::fresh_seed();
  check_model(ctx(), compact_depth_net({64, 48}, seed), seed);
}

// With random weights the transformer head's fp16 error is heavy-tailed: over 160 seeds the
// relative L2 was 3.1e-3 median, 6.7e-3 p90, 1.5e-2 p99, 1.7e-2 worst; CI drew 2.8e-2 (seed
// 2547249134) against the shared 2e-2. A broken fp16 path (packing, layout) is off by O(1).
// The transformer head amplifies rounding: Vulkan fp32 against the reference reads 9e-7 typically
// and up to 1.0e-5 on this network, at most 7e-7 without the head (docs/validation-log.md); 3e-5.
TEST_F(VulkanTest, OnnxTrudepthNet) {
  const uint64_t seed = pensight::testing::fresh_seed();
  check_model(ctx(), trudepth_net({128, 96}, 0.5f, seed), seed, 8e-2, 3e-5);
}

// The TRUDepth encoder-decoder (MobileNetV2, ReLU6, residuals, prior at every scale) without
// the transformer head, so that OpenCV DNN checks it too.
TEST_F(VulkanTest, OnnxTrudepthEncoderDecoder) {
  const uint64_t seed = pensight::testing::fresh_seed();
  check_model(ctx(), trudepth_net({128, 96}, 0.5f, seed, DepthHead::kConvSoftplus), seed);
}

// The shipped depth network as PyTorch wrote it (models/compact_depth.onnx): our CPU and Vulkan
// executors against OpenCV DNN and ONNX Runtime reading that same file.
TEST_F(VulkanTest, OnnxShippedDepthModel) {
  const fs::path file = fs::path(std::getenv("PENSIGHT_SOURCE_DIR")) / "models/compact_depth.onnx";
  const std::optional<std::string> bytes = read_file_bytes(file);
  ASSERT_TRUE(bytes) << file;
  ASSERT_NO_THROW(check_onnx_bytes(*bytes));
  const Graph g = import_onnx_bytes(*bytes, file.string());
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  const auto inputs = random_inputs(g, rng);
  const auto want = run_cpu(g, inputs);
  VkModel model(ctx(), g);
  model.fill_activations(pensight::testing::kPoison);
  const double vk_error = relative_l2(model.run(inputs)[0], want[0]);
  std::printf("Vulkan fp32 vs CPU executor: relative L2 %.2e\n", vk_error);
  EXPECT_LT(vk_error, 1e-5);
  const double cv_error = relative_l2(run_opencv(*bytes, g, inputs)[0], want[0]);
  std::printf("OpenCV DNN vs ours: relative L2 %.2e\n", cv_error);
  EXPECT_LT(cv_error, 1e-4);
  const fs::path dir = ort_dir();
  if (dir.empty()) {
    std::printf("ONNX Runtime check skipped: no node_modules/onnxruntime-node\n");
    return;
  }
  const double ort_error = relative_l2(run_ort(dir, *bytes, g, inputs)[0], want[0]);
  std::printf("ONNX Runtime vs ours: relative L2 %.2e\n", ort_error);
  EXPECT_LT(ort_error, 1e-4);
}

TEST(Onnx, Fp16WeightsExportPassesTheCheckerAndStaysClose) {
  const uint64_t seed = pensight::testing::fresh_seed();
  const Graph g = compact_depth_net({32, 24}, seed);
  std::mt19937_64 rng(seed);
  const auto inputs = random_inputs(g, rng);
  const std::string bytes = export_onnx_bytes(g, {.fp16_weights = true});
  ASSERT_NO_THROW(check_onnx_bytes(bytes));
  EXPECT_LT(bytes.size(), export_onnx_bytes(g).size() * 6 / 10);
  const double e = relative_l2(run_cpu(import_onnx_bytes(bytes), inputs)[0], run_cpu(g, inputs)[0]);
  EXPECT_GT(e, 0.0);
  EXPECT_LT(e, 1e-2);
}

TEST(Onnx, BatchNormIsFoldedIntoConv) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  Graph g;
  const int x = g.add_input("x", {1, 3, 9, 8});
  Attrs a;
  a.pads = {1, 1, 1, 1};
  const int c = g.add(Op::kConv,
                      {x, g.add_constant("w", random_tensor({4, 3, 3, 3}, rng)),
                       g.add_constant("b", random_tensor({4}, rng))},
                      a, "conv");
  g.mark_output(g.add(Op::kRelu, {c}, {}, "relu"));
  onnx::ModelProto m;
  ASSERT_TRUE(m.ParseFromString(export_onnx_bytes(g)));
  // Insert BatchNormalization between the Conv and the Relu.
  auto* graph = m.mutable_graph();
  const Tensor scale = random_tensor({4}, rng, 0.5f, 2.f), shift = random_tensor({4}, rng),
               mean = random_tensor({4}, rng), var = random_tensor({4}, rng, 0.1f, 2.f);
  for (const auto& [name, t] :
       {std::pair{"bn_s", &scale}, {"bn_b", &shift}, {"bn_m", &mean}, {"bn_v", &var}}) {
    auto* init = graph->add_initializer();
    init->set_name(name);
    init->add_dims(4);
    init->set_data_type(onnx::TensorProto::FLOAT);
    for (float v : t->data) init->add_float_data(v);
  }
  onnx::NodeProto bn;
  bn.set_op_type("BatchNormalization");
  bn.set_name("bn");
  for (const char* in : {"conv:out", "bn_s", "bn_b", "bn_m", "bn_v"}) bn.add_input(in);
  bn.add_output("bn:out");
  graph->mutable_node(1)->set_input(0, "bn:out");
  *graph->mutable_node()->Add() = bn;
  // Keep topological order: conv, bn, relu.
  graph->mutable_node()->SwapElements(1, 2);
  std::string bytes;
  m.SerializeToString(&bytes);
  ASSERT_NO_THROW(check_onnx_bytes(bytes));
  const Graph folded = import_onnx_bytes(bytes);
  ASSERT_EQ(folded.nodes().size(), 2u);  // Conv, Relu
  EXPECT_EQ(folded.nodes()[0].op, Op::kConv);
  // Reference: conv, then BN by its formula, then relu.
  Graph conv_only;
  const int x2 = conv_only.add_input("x", {1, 3, 9, 8});
  conv_only.mark_output(
      conv_only.add(Op::kConv,
                    {x2, conv_only.add_constant("w", {g.value(1).shape, g.value(1).data}),
                     conv_only.add_constant("b", {g.value(2).shape, g.value(2).data})},
                    a));
  const std::vector<Tensor> in = {random_tensor({1, 3, 9, 8}, rng)};
  Tensor want = run_cpu(conv_only, in)[0];
  for (size_t i = 0; i < want.data.size(); ++i) {
    const size_t ch = i / 72;
    const double v =
        (want.data[i] - mean.data[ch]) / std::sqrt(var.data[ch] + 1e-5) * scale.data[ch] +
        shift.data[ch];
    want.data[i] = static_cast<float>(std::max(v, 0.0));
  }
  testutil::expect_close(run_cpu(folded, in)[0], want, 1e-5f);
}

std::string import_error(const std::string& bytes) {
  try {
    import_onnx_bytes(bytes, "test.onnx");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Onnx, RefusesUnsupportedOpsAndDynamicShapesWithNames) {
  Graph g;
  g.mark_output(g.add(Op::kRelu, {g.add_input("x", {1, 2, 3, 4})}, {}, "act"));
  onnx::ModelProto m;
  ASSERT_TRUE(m.ParseFromString(export_onnx_bytes(g)));
  onnx::ModelProto bad_op = m;
  bad_op.mutable_graph()->mutable_node(0)->set_op_type("NonMaxSuppression");
  std::string bytes;
  bad_op.SerializeToString(&bytes);
  const std::string e1 = import_error(bytes);
  EXPECT_NE(e1.find("NonMaxSuppression"), std::string::npos) << e1;
  EXPECT_NE(e1.find("'act'"), std::string::npos) << e1;
  EXPECT_NE(e1.find("hint"), std::string::npos) << e1;

  onnx::ModelProto shape_op = m;
  shape_op.mutable_graph()->mutable_node(0)->set_op_type("Shape");
  shape_op.SerializeToString(&bytes);
  EXPECT_NE(import_error(bytes).find("static shapes"), std::string::npos) << import_error(bytes);

  onnx::ModelProto dynamic = m;
  auto* dim = dynamic.mutable_graph()
                  ->mutable_input(0)
                  ->mutable_type()
                  ->mutable_tensor_type()
                  ->mutable_shape()
                  ->mutable_dim(0);
  dim->set_dim_param("batch");
  dynamic.SerializeToString(&bytes);
  const std::string e3 = import_error(bytes);
  EXPECT_NE(e3.find("dynamic"), std::string::npos) << e3;
  EXPECT_NE(e3.find("batch"), std::string::npos) << e3;

  EXPECT_NE(import_error("not a model").find("not an ONNX model"), std::string::npos);
  EXPECT_THROW(import_onnx("/nonexistent/model.onnx"), Error);
}

TEST(Onnx, ExportMakesTensorNamesUnique) {
  Graph g;
  const int x = g.add_input("x", {1, 2, 3, 4});
  const int a = g.add(Op::kRelu, {x}, {}, "same");
  g.mark_output(g.add(Op::kSigmoid, {a}, {}, "same"));
  const std::string bytes = export_onnx_bytes(g);
  ASSERT_NO_THROW(check_onnx_bytes(bytes));
  const std::vector<Tensor> in = {
      random_tensor({1, 2, 3, 4}, *std::make_unique<std::mt19937_64>(5))};
  testutil::expect_close(run_cpu(import_onnx_bytes(bytes), in)[0], run_cpu(g, in)[0], 0);
}

TEST(Onnx, ExportWritesAtomically) {
  const fs::path dir =
      fs::temp_directory_path() / ("pensight_export_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Graph g = all_ops_net(1);
  export_onnx(g, dir / "m.onnx");
  EXPECT_TRUE(fs::exists(dir / "m.onnx"));
  // No temporary file is left beside m.onnx.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_EQ(import_onnx(dir / "m.onnx").nodes().size(), g.nodes().size());
  EXPECT_THROW(export_onnx(g, dir / "missing" / "m.onnx"), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pensight::kernels
