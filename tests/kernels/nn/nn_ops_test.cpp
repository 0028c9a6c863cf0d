// Every op of the engine: the Vulkan executor against the CPU reference on random inputs, with
// every activation buffer poisoned (NaN) before the run.
#include <gtest/gtest.h>

#include "core/error.h"
#include "kernels/nn/nn.h"
#include "kernels/nn/nn_models.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "runtime/vk_buffer.h"
#include "tests/kernels/nn/nn_test_util.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::kernels {
namespace {

using testing::VulkanTest;
using testutil::random_tensor;

class NnOps : public VulkanTest {
 protected:
  NnOps() : rng_(pensight::testing::fresh_seed()) {}

  int input(Dims shape, float lo = -1, float hi = 1) {
    inputs_.push_back(random_tensor(shape, rng_, lo, hi));
    return g_.add_input("x" + std::to_string(inputs_.size()), std::move(shape));
  }
  int constant(Dims shape, float lo = -1, float hi = 1) {
    return g_.add_constant("c" + std::to_string(g_.values().size()),
                           random_tensor(std::move(shape), rng_, lo, hi));
  }
  // Marks `out` as the output, runs both executors and compares.
  void check(int out, float tol = 1e-4f, VkModelOptions options = {}) {
    g_.mark_output(out);
    const auto want = run_cpu(g_, inputs_);
    VkModel model(ctx(), g_, options);
    model.fill_activations(pensight::testing::kPoison);
    const auto got = model.run(inputs_);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) testutil::expect_close(got[i], want[i], tol);
    // fp16 storage: the same graph with half-precision activations and weights.
    if (!ctx().info().fp16_storage) return;
    options.fp16_storage = true;
    VkModel half(ctx(), g_, options);
    half.fill_activations(pensight::testing::kPoison);
    const auto got16 = half.run(inputs_);
    for (size_t i = 0; i < got16.size(); ++i) {
      EXPECT_LT(testutil::relative_l2(got16[i], want[i]), 1e-2) << "fp16 storage, output " << i;
    }
  }

  std::mt19937_64 rng_;
  Graph g_;
  std::vector<Tensor> inputs_;
};

Attrs conv_attrs(int stride, int pad, int dilation = 1, int group = 1) {
  Attrs a;
  a.stride = {stride, stride};
  a.pads = {pad, pad, pad, pad};
  a.dilation = {dilation, dilation};
  a.group = group;
  return a;
}

TEST_F(NnOps, Conv3x3Padded) {
  check(g_.add(Op::kConv, {input({1, 3, 17, 19}), constant({8, 3, 3, 3}), constant({8})},
               conv_attrs(1, 1)));
}
TEST_F(NnOps, ConvStrideDilationAsymmetricPadsNoBias) {
  Attrs a = conv_attrs(2, 0, 2);
  a.pads = {1, 0, 2, 3};
  a.stride = {2, 3};
  check(g_.add(Op::kConv, {input({2, 4, 21, 18}), constant({12, 4, 3, 3})}, a));
}
TEST_F(NnOps, ConvGroupsOddChannelsPerGroup) {
  check(g_.add(Op::kConv, {input({1, 6, 11, 13}), constant({6, 3, 3, 3}), constant({6})},
               conv_attrs(1, 1, 1, 2)));
}
TEST_F(NnOps, ConvDepthwiseStride2FusedRelu6) {
  const int c = g_.add(Op::kConv, {input({1, 16, 20, 15}), constant({16, 1, 3, 3}), constant({16})},
                       conv_attrs(2, 1, 1, 16));
  Attrs clip;
  clip.alpha = 0;
  clip.beta = 6;
  check(g_.add(Op::kClip, {g_.add(Op::kMul, {c, constant({1}, 4, 5)})}, clip));
}
TEST_F(NnOps, ConvPointwiseFusedActivations) {
  for (Op act : {Op::kRelu, Op::kLeakyRelu, Op::kSigmoid, Op::kClip}) {
    g_ = Graph();
    inputs_.clear();
    Attrs a;
    a.alpha = act == Op::kClip ? -0.5f : 0.1f;
    a.beta = 0.5f;
    check(g_.add(
        act, {g_.add(Op::kConv, {input({1, 8, 9, 7}), constant({16, 8, 1, 1}), constant({16})})},
        a));
  }
}
TEST_F(NnOps, ConvTranspose) {
  Attrs a = conv_attrs(2, 1);
  check(
      g_.add(Op::kConvTranspose, {input({1, 4, 7, 9}), constant({4, 6, 4, 4}), constant({6})}, a));
}
TEST_F(NnOps, ConvTransposeOutputPaddingGroupsFusedRelu) {
  Attrs a = conv_attrs(2, 1, 1, 2);
  a.output_padding = {1, 1};
  check(g_.add(Op::kRelu,
               {g_.add(Op::kConvTranspose, {input({2, 4, 5, 6}), constant({4, 3, 3, 3})}, a)}));
}
TEST_F(NnOps, Unary) {
  for (Op op : {Op::kRelu, Op::kLeakyRelu, Op::kSigmoid, Op::kSoftplus, Op::kSqrt, Op::kClip}) {
    g_ = Graph();
    inputs_.clear();
    Attrs a;
    a.alpha = op == Op::kClip ? -0.3f : 0.2f;
    a.beta = 0.4f;
    const float lo = op == Op::kSqrt ? 0.f : -30.f;
    check(g_.add(op, {input({2, 3, 5, 7}, lo, 30.f)}, a));
  }
}
TEST_F(NnOps, BinaryBroadcast) {
  for (Op op : {Op::kAdd, Op::kSub, Op::kMul, Op::kDiv, Op::kPow}) {
    g_ = Graph();
    inputs_.clear();
    const int x = input({2, 3, 4, 5}, 0.5f, 2.f);
    const int full = g_.add(op, {x, input({2, 3, 4, 5}, 0.5f, 2.f)});
    const int chan = g_.add(op, {full, constant({1, 3, 1, 1}, 0.5f, 2.f)});
    const int row = g_.add(op, {constant({5}, 0.5f, 1.5f), chan});
    check(g_.add(op, {row, constant({1}, 0.5f, 1.5f)}), 2e-4f);
  }
}
TEST_F(NnOps, PowSquareOfNegatives) {
  Tensor two{{1}, {2.f}};
  check(g_.add(Op::kPow, {input({3, 17}), g_.add_constant("two", two)}));
}
TEST_F(NnOps, Concat) {
  Attrs a;
  a.axis = 1;
  const int c1 =
      g_.add(Op::kConcat, {input({2, 3, 4, 5}), input({2, 1, 4, 5}), input({2, 2, 4, 5})}, a);
  a.axis = -1;
  check(g_.add(Op::kConcat, {c1, input({2, 6, 4, 3})}, a));
}
TEST_F(NnOps, Resize) {
  for (ResizeMode mode :
       {ResizeMode::kNearest, ResizeMode::kLinearHalfPixel, ResizeMode::kLinearAlignCorners}) {
    for (std::array<int64_t, 2> size : {std::array<int64_t, 2>{10, 14}, {7, 19}, {3, 2}}) {
      g_ = Graph();
      inputs_.clear();
      Attrs a;
      a.resize = mode;
      a.sizes = size;
      check(g_.add(Op::kResize, {input({1, 3, 5, 7})}, a));
    }
  }
}
TEST_F(NnOps, Pools) {
  Attrs mx;
  mx.kernel = {3, 3};
  mx.stride = {2, 2};
  mx.pads = {1, 1, 1, 1};
  const int x = input({1, 4, 13, 10});
  const int m = g_.add(Op::kMaxPool, {x}, mx);
  Attrs av = mx;
  av.stride = {1, 1};
  const int a1 = g_.add(Op::kAveragePool, {m}, av);
  av.count_include_pad = true;
  const int a2 = g_.add(Op::kAveragePool, {a1}, av);
  Attrs a3;
  a3.kernel = {2, 2};
  a3.stride = {2, 2};
  const int p = g_.add(Op::kAveragePool, {a2}, a3);
  g_.mark_output(g_.add(Op::kGlobalAveragePool, {x}));
  check(p);
}
TEST_F(NnOps, MatMul) {
  g_.mark_output(g_.add(Op::kMatMul, {input({2, 5, 7}), constant({7, 3})}));
  g_.mark_output(g_.add(Op::kMatMul, {input({2, 3, 5, 7}), input({2, 3, 7, 4})}));
  check(g_.add(Op::kMatMul, {input({33, 65}), input({65, 40})}));
}
TEST_F(NnOps, Gemm) {
  Attrs a;
  a.trans_b = true;
  a.alpha = 0.7f;
  a.beta = 1.3f;
  const int y1 = g_.add(Op::kGemm, {input({5, 20}), constant({18, 20}), constant({18})}, a);
  Attrs b;
  b.trans_a = true;
  b.alpha = 1;
  b.beta = 1;
  check(g_.add(Op::kGemm, {y1, constant({5, 9}), constant({18, 9})}, b));
}
TEST_F(NnOps, Softmax) {
  Attrs a;
  a.axis = -1;
  const int s1 = g_.add(Op::kSoftmax, {input({2, 3, 4, 50}, -5, 5)}, a);
  a.axis = 1;
  check(g_.add(Op::kSoftmax, {s1}, a));
}
TEST_F(NnOps, TransposeReshapeFlatten) {
  Attrs t;
  t.ints = {0, 2, 3, 1};
  const int x = g_.add(Op::kTranspose, {input({2, 3, 4, 5})}, t);  // [2,4,5,3]
  Attrs r;
  r.ints = {0, -1, 3};
  const int y = g_.add(Op::kReshape, {x}, r);  // [2,20,3]
  Attrs t3;
  t3.ints = {0, 2, 1};
  const int z = g_.add(Op::kRelu, {g_.add(Op::kTranspose, {y}, t3)});  // [2,3,20]
  Attrs f;
  f.axis = 1;
  check(g_.add(Op::kFlatten, {z}, f));  // graph output: copied, not aliased
}
TEST_F(NnOps, ReshapeOfAConstant) {
  Attrs r;
  r.ints = {1, 6, 1, 1};
  check(g_.add(Op::kAdd, {input({1, 6, 5, 4}), g_.add(Op::kReshape, {constant({6})}, r)}));
}
TEST_F(NnOps, Slice) {
  Attrs a;
  a.starts = {1, -4, 0};
  a.ends = {3, 1000, -1};
  a.axes = {1, 2, 3};
  a.steps = {1, 2, 3};
  check(g_.add(Op::kSlice, {input({2, 4, 9, 11})}, a));
}
TEST_F(NnOps, ReduceMean) {
  Attrs a;
  a.axes = {-1};
  g_.mark_output(g_.add(Op::kReduceMean, {input({2, 3, 17})}, a));
  Attrs b;
  b.axes = {1, 2};
  b.keepdims = false;
  check(g_.add(Op::kReduceMean, {input({2, 5, 6, 7})}, b));
}
// A whole 320x240 plane per output: more elements than llvmpipe lets one loop run (65535), which
// the depth network's per-frame prior mean needs.
TEST_F(NnOps, MeanOverAWholeImage) {
  // Inputs of both signs whose mean is away from zero: a mean of inputs in [-1, 1] over 153600
  // elements is ~1e-3 and can be ~1e-6, below what fp16 storage of its inputs resolves (their
  // rounding alone moves it by ~4e-7), where the relative check would fail a correct kernel.
  const int x = input({1, 2, 240, 320}, -0.5f, 1.f);
  g_.mark_output(g_.add(Op::kGlobalAveragePool, {x}));
  Attrs a;
  a.axes = {1, 2, 3};
  check(g_.add(Op::kReduceMean, {x}, a));
}
TEST_F(NnOps, LayerNorm) {
  Attrs a;
  a.axis = -1;
  a.epsilon = 1e-5f;
  const int x =
      g_.add(Op::kLayerNorm, {input({2, 10, 24}, -3, 5), constant({24}), constant({24})}, a);
  check(g_.add(Op::kLayerNorm, {x, constant({24})}, a));
}

TEST_F(NnOps, PlanningReusesBuffers) {
  int x = input({1, 8, 32, 32});
  // Positive biases keep every ReLU output alive: with biases in [-1, 1] six layers can end all
  // zero, where fp16 and fp32 agree exactly and the rounding check below says nothing.
  for (int i = 0; i < 6; ++i) {
    x = g_.add(Op::kConv, {x, constant({8, 8, 3, 3}, -0.2f, 0.2f), constant({8}, 0.0f, 0.5f)},
               conv_attrs(1, 1));
    x = g_.add(Op::kRelu, {x});
  }
  g_.mark_output(x);
  const auto want = run_cpu(g_, inputs_);
  VkModel fused(ctx(), g_);
  VkModel unfused(ctx(), g_, {.fuse_activations = false});
  EXPECT_EQ(fused.num_dispatches(), 6u);
  EXPECT_EQ(unfused.num_dispatches(), 12u);
  EXPECT_LE(unfused.activation_bytes() * 3, unfused.unplanned_activation_bytes());
  if (ctx().info().fp16_storage) {
    VkModel half(ctx(), g_, {.fp16_storage = true});
    EXPECT_EQ(half.activation_bytes() * 2, fused.activation_bytes());
    half.fill_activations(pensight::testing::kPoison);
    const double e = testutil::relative_l2(half.run(inputs_)[0], want[0]);
    EXPECT_GT(e, 1e-6);  // really rounded to half precision
    EXPECT_LT(e, 1e-2);
  }
  for (VkModel* m : {&fused, &unfused}) {
    m->fill_activations(pensight::testing::kPoison);
    testutil::expect_close(m->run(inputs_)[0], want[0]);
  }
}

TEST(NnGraph, RejectsMismatchedShapesNamingTheNode) {
  Graph g;
  const int x = g.add_input("image", {1, 3, 8, 8});
  const int w = g.add_constant("w", {{4, 2, 3, 3}, std::vector<float>(72)});
  try {
    g.add(Op::kConv, {x, w}, {}, "enc.conv1");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("enc.conv1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Conv"), std::string::npos) << e.what();
  }
  EXPECT_THROW(g.add(Op::kAdd, {x, g.add_input("y", {1, 2, 8, 8})}), Error);
  EXPECT_THROW(g.add_input("dyn", {-1, 3, 8, 8}), Error);
  EXPECT_THROW(run_cpu(g, {}), Error);
}

}  // namespace
}  // namespace pensight::kernels

namespace pensight::kernels {
namespace {

// S1/S2 written by the sparse_prior kernel straight into the model's "prior" input buffer, then
// the compact net, recorded into one stream and submitted once; against the CPU prior + CPU
// reference executor. The stream's hazard tracking orders the net after the prior.
TEST_F(VulkanTest, SparsePriorFeedsTheModelInputOnDevice) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  const Graph g = compact_depth_net({48, 32}, rng());
  const kernels::SparsePriorShape shape{48, 32, 10};
  std::uniform_real_distribution<float> ux(0, 47), uy(0, 31), ud(1, 4);
  std::vector<kernels::SparsePoint> pts(20);
  for (auto& p : pts) p = {ux(rng), uy(rng), ud(rng)};
  std::vector<Tensor> inputs = {random_tensor({1, 1, 32, 48}, rng, 0, 1),
                                {{1, 2, 32, 48}, std::vector<float>(2 * 32 * 48)}};
  kernels::sparse_prior_cpu(shape, pts, inputs[1].data);
  const auto want = run_cpu(g, inputs);

  VkModel model(ctx(), g);
  model.fill_activations(pensight::testing::kPoison);
  model.input_buffer(0).upload(inputs[0].data.data(), inputs[0].data.size() * sizeof(float));
  const kernels::SparsePriorVk prior(ctx(), shape);
  vk::Buffer point_buf(ctx(), pts.size() * sizeof(kernels::SparsePoint));
  point_buf.upload(pts.data(), pts.size() * sizeof(kernels::SparsePoint));
  vk::TypedBuffer<kernels::SparsePriorParams> params(ctx(), 1);
  params.fill({static_cast<uint32_t>(pts.size())});
  vk::CommandStream stream(ctx());
  prior.record(stream, point_buf, params, model.input_buffer(1));
  model.record(stream);
  EXPECT_EQ(stream.num_commands(), 1 + model.num_dispatches());
  stream.submit_and_wait();
  Tensor got{want[0].shape, std::vector<float>(want[0].data.size())};
  model.output_buffer(0).download(got.data.data(), got.data.size() * sizeof(float));
  testutil::expect_close(got, want[0], 1e-4f);
}

// One network input holding the image in channel 0 and S1/S2 in channels 1, 2: the prior lands at
// an offset inside the model's input buffer, and prior + model run as one submission. fp16
// storage too, where its fp32 input buffer is converted on the device after the prior.
TEST_F(VulkanTest, SparsePriorAtAnOffsetAndModelInOneSubmission) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  const int w = 40, h = 24;
  const size_t plane = static_cast<size_t>(w) * h;
  Graph g;
  const int x = g.add_input("rgbd", {1, 3, h, w});
  Attrs same;
  same.pads = {1, 1, 1, 1};
  const int c1 = g.add(Op::kConv,
                       {x, g.add_constant("w1", random_tensor({8, 3, 3, 3}, rng)),
                        g.add_constant("b1", random_tensor({8}, rng))},
                       same);
  const int r1 = g.add(Op::kRelu, {c1});
  g.mark_output(g.add(Op::kConv, {r1, g.add_constant("w2", random_tensor({1, 8, 1, 1}, rng))}));

  const kernels::SparsePriorShape shape{w, h, 6};
  std::uniform_real_distribution<float> ux(0, w - 1), uy(0, h - 1), ud(1, 4);
  std::vector<kernels::SparsePoint> pts(12);
  for (auto& p : pts) p = {ux(rng), uy(rng), ud(rng)};
  const Tensor image = random_tensor({1, 1, h, w}, rng, 0, 1);
  Tensor input{{1, 3, h, w}, std::vector<float>(3 * plane)};
  std::copy(image.data.begin(), image.data.end(), input.data.begin());
  kernels::sparse_prior_cpu(shape, pts, std::span(input.data).subspan(plane));
  const auto want = run_cpu(g, std::vector<Tensor>{input});

  const kernels::SparsePriorVk prior(ctx(), shape);
  vk::Buffer point_buf(ctx(), pts.size() * sizeof(kernels::SparsePoint));
  point_buf.upload(pts.data(), pts.size() * sizeof(kernels::SparsePoint));
  vk::TypedBuffer<kernels::SparsePriorParams> params(ctx(), 1);
  params.fill({static_cast<uint32_t>(pts.size())});
  for (const bool fp16 : {false, true}) {
    if (fp16 && !ctx().info().fp16_storage) continue;
    SCOPED_TRACE(fp16 ? "fp16 storage" : "fp32");
    VkModel model(ctx(), g, {.fp16_storage = fp16});
    model.fill_activations(pensight::testing::kPoison);
    model.input_buffer(0).upload(image.data.data(), plane * sizeof(float));
    vk::CommandStream stream(ctx());
    prior.record(stream, point_buf, params, model.input_buffer(0), static_cast<uint32_t>(plane));
    model.record(stream);
    stream.submit_and_wait();
    Tensor got{want[0].shape, std::vector<float>(want[0].data.size())};
    model.output_buffer(0).download(got.data.data(), got.data.size() * sizeof(float));
    if (fp16) {
      EXPECT_LT(testutil::relative_l2(got, want[0]), 1e-2);
    } else {
      testutil::expect_close(got, want[0], 1e-4f);
    }
  }
}

// Two models of one graph on one context: the second builds no pipeline, and reports the same
// distinct pipelines as the first.
TEST_F(VulkanTest, ModelsShareTheirPipelines) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  const Graph g = compact_depth_net({24, 16}, rng());
  const VkModel first(ctx(), g);
  const size_t built = ctx().num_pipelines();
  const VkModel second(ctx(), g);
  EXPECT_EQ(ctx().num_pipelines(), built);
  EXPECT_GT(first.num_pipelines(), 0u);
  EXPECT_LE(first.num_pipelines(), built);
  EXPECT_EQ(second.num_pipelines(), first.num_pipelines());
}

}  // namespace
}  // namespace pensight::kernels
