#pragma once
// A small neural-network engine: a static graph of fp32 NCHW tensor ops (ONNX semantics), a CPU
// reference executor (Eigen) and a Vulkan executor that plans buffers and builds pipelines once
// per model and shape. Graphs come from the builder below or from ONNX (kernels/nn/nn_onnx.h).
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"
#include "runtime/vk_stream.h"

namespace pensight::kernels {

using Dims = std::vector<int64_t>;
int64_t num_elements(const Dims& shape);
std::string to_string(const Dims& shape);

struct Tensor {
  Dims shape;
  std::vector<float> data;  // row-major (NCHW for images)
};

enum class Op {
  kConv,           // inputs X, W[Cout, Cin/group, kh, kw], optional B[Cout]
  kConvTranspose,  // inputs X, W[Cin, Cout/group, kh, kw], optional B[Cout]
  kRelu,
  kClip,       // attrs.alpha = min, attrs.beta = max (ReLU6: 0, 6)
  kLeakyRelu,  // attrs.alpha = slope
  kSigmoid,
  kSoftplus,
  kSqrt,
  kAdd,  // binary ops broadcast numpy-style (rank <= 4)
  kSub,
  kMul,
  kDiv,
  kPow,
  kConcat,       // attrs.axis
  kResize,       // attrs.sizes = output H, W; attrs.resize = mode + coordinates
  kMaxPool,      // attrs.kernel/stride/pads (no dilation)
  kAveragePool,  // attrs.count_include_pad
  kGlobalAveragePool,
  kMatMul,      // [.., M, K] x [.., K, N] (B rank 2 or the same batch dims)
  kGemm,        // A[M,K], B[K,N] (trans_a/b), optional C broadcast to [M,N]; alpha, beta
  kSoftmax,     // attrs.axis
  kTranspose,   // attrs.ints = perm
  kReshape,     // attrs.ints = output shape (ONNX rules: 0 copies, -1 infers)
  kFlatten,     // attrs.axis
  kSlice,       // attrs.starts/ends/axes/steps (ONNX rules, clamped)
  kReduceMean,  // attrs.axes, attrs.keepdims
  kLayerNorm,   // inputs X, scale, optional bias, over axes [axis, rank); attrs.epsilon
};
const char* to_string(Op op);

enum class ResizeMode { kNearest, kLinearHalfPixel, kLinearAlignCorners };

struct Attrs {
  std::array<int, 2> kernel{1, 1};
  std::array<int, 2> stride{1, 1};
  std::array<int, 2> dilation{1, 1};
  std::array<int, 4> pads{0, 0, 0, 0};  // top, left, bottom, right
  std::array<int, 2> output_padding{0, 0};
  int group = 1;
  bool count_include_pad = false;
  float alpha = 0;  // Clip min, LeakyRelu slope, Gemm alpha
  float beta = 0;   // Clip max, Gemm beta
  float epsilon = 1e-5f;
  int axis = 1;
  bool keepdims = true;
  bool trans_a = false, trans_b = false;
  ResizeMode resize = ResizeMode::kNearest;
  std::array<int64_t, 2> sizes{0, 0};
  std::vector<int64_t> ints;  // Transpose perm, Reshape shape
  std::vector<int64_t> starts, ends, axes, steps;
};

struct Value {
  std::string name;
  Dims shape;
  bool is_constant = false;
  std::vector<float> data;  // constants only
};

struct Node {
  Op op;
  std::string name;
  std::vector<int> inputs;  // value ids
  int output = -1;
  Attrs attrs;
};

// Nodes are added in execution order; each output shape is inferred (and checked) when added.
class Graph {
 public:
  int add_input(std::string name, Dims shape);
  int add_constant(std::string name, Tensor tensor);
  // Throws pensight::Error naming the op, the node and the mismatch when the inputs do not fit.
  int add(Op op, std::vector<int> inputs, Attrs attrs = {}, std::string name = {});
  void mark_output(int value);

  const std::vector<Value>& values() const { return values_; }
  std::vector<Value>& values() { return values_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<int>& inputs() const { return inputs_; }
  const std::vector<int>& outputs() const { return outputs_; }
  const Value& value(int id) const { return values_.at(static_cast<size_t>(id)); }
  // Multiply-adds x 2 of the conv/matmul/gemm nodes (elementwise work excluded).
  double flops() const;

 private:
  std::vector<Value> values_;
  std::vector<Node> nodes_;
  std::vector<int> inputs_, outputs_;
};

// CPU reference executor (Eigen GEMM for conv/matmul): one tensor per graph output.
std::vector<Tensor> run_cpu(const Graph& graph, std::span<const Tensor> inputs);

struct VkModelOptions {
  // Fuse an activation (Relu, Clip, LeakyRelu, Sigmoid) into the Conv that feeds it only.
  bool fuse_activations = true;
  // Activations and weights stored as float16 (arithmetic stays fp32), halving memory traffic.
  // Needs storageBuffer16BitAccess (vk::DeviceInfo::fp16_storage). Graph inputs and outputs stay
  // fp32: they are converted on the device at the start and end of the recorded stream.
  bool fp16_storage = false;
};

// Vulkan executor. The constructor borrows every pipeline from the context (shared with other
// models and kernel families on it), uploads the constants, assigns each intermediate tensor to
// a pooled buffer (a buffer is reused once its tensor's last reader has run) and plans the
// graph's commands once. record() appends them to a caller's stream, e.g. after the kernels that
// fill input_buffer(); submit() and run() replay the model's own stream, recorded the same way.
class VkModel {
 public:
  VkModel(const vk::Context& ctx, const Graph& graph, VkModelOptions options = {});
  ~VkModel();
  VkModel(VkModel&&) noexcept;
  VkModel& operator=(VkModel&&) noexcept;

  // Device buffers of the graph inputs (fill them directly, e.g. with SparsePriorVk) and outputs.
  vk::Buffer& input_buffer(size_t i);
  vk::Buffer& output_buffer(size_t i);
  // Fills every activation buffer (tests: poison them so an unwritten element shows).
  void fill_activations(float value);
  // Appends the whole graph (its dispatches on the model's own buffers) to `stream`; the stream's
  // hazard tracking orders it after whatever the caller recorded into the input buffers. The
  // stream must not run while the model's own submit() does: they share the buffers.
  void record(vk::CommandStream& stream) const;
  // Runs the model's own recorded stream (inputs already in their buffers).
  void submit();
  // Upload, submit, download.
  std::vector<Tensor> run(std::span<const Tensor> inputs);

  size_t num_dispatches() const;
  // Distinct pipelines this model uses (each built once per context, shared with other users).
  size_t num_pipelines() const;
  // Bytes of the pooled activation buffers, and what one buffer per tensor would take.
  size_t activation_bytes() const;
  size_t unplanned_activation_bytes() const;
  std::vector<vk::DispatchTime> timings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight::kernels
