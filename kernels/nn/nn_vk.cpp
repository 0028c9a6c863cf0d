// Vulkan executor: fuses activations into convolutions, plans activation buffers by liveness,
// borrows one pipeline per (shader, specialization) from the context and plans the graph's
// commands once, so they can be appended to any command stream.
#include <Eigen/Core>
#include <algorithm>
#include <bit>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <set>

#include "core/error.h"
#include "kernels/kernel_shader.h"
#include "kernels/nn/nn.h"
#include "kernels/nn/nn_detail.h"

namespace pensight::kernels {
namespace {

uint32_t u32(int64_t v) {
  return static_cast<uint32_t>(v);
}
uint32_t fbits(float v) {
  return std::bit_cast<uint32_t>(v);
}

// Activation codes of nn_act.glsl.
std::optional<uint32_t> act_code(Op op) {
  switch (op) {
    case Op::kRelu:
      return 1;
    case Op::kClip:
      return 2;
    case Op::kLeakyRelu:
      return 3;
    case Op::kSigmoid:
      return 4;
    case Op::kSoftplus:
      return 5;
    case Op::kSqrt:
      return 6;
    default:
      return std::nullopt;
  }
}

uint32_t binary_code(Op op) {
  switch (op) {
    case Op::kAdd:
      return 0;
    case Op::kSub:
      return 1;
    case Op::kMul:
      return 2;
    case Op::kDiv:
      return 3;
    default:
      return 4;
  }
}

struct Copy4 {
  uint32_t shape[4], ss[4], ds[4], src_off, dst_off, count;
};

// A node as executed: the conv's output may be replaced by the fused activation's.
struct ExecNode {
  const Node* node;
  int output;
  Op act = Op::kRelu;
  bool fused = false;
  Attrs act_attrs;
};

// One command of the graph as planned in the constructor: a dispatch, or a copy when `pipeline`
// is null. The buffers are the model's own, so the same list can be recorded into any stream.
struct Step {
  const vk::Pipeline* pipeline = nullptr;
  std::vector<vk::Binding> bindings;
  vk::Groups groups;
  std::vector<uint32_t> push;  // push-constant words
  std::string name;
  const vk::Buffer* src = nullptr;
  const vk::Buffer* dst = nullptr;
  size_t bytes = 0;
};

// Collects the graph's commands through the same calls vk::CommandStream takes.
struct StepList {
  std::vector<Step> steps;

  void dispatch(const vk::Pipeline& pipeline, std::initializer_list<vk::Binding> buffers,
                vk::Groups groups, const void* push, size_t push_bytes, std::string name) {
    Step step{&pipeline, buffers, groups, std::vector<uint32_t>(push_bytes / 4), std::move(name)};
    if (push_bytes) std::memcpy(step.push.data(), push, push_bytes);
    steps.push_back(std::move(step));
  }
  template <class Push>
  void dispatch(const vk::Pipeline& pipeline, std::initializer_list<vk::Binding> buffers,
                vk::Groups groups, const Push& push, std::string name) {
    dispatch(pipeline, buffers, groups, &push, sizeof(Push), std::move(name));
  }
  void copy(const vk::Buffer& src, const vk::Buffer& dst, size_t bytes) {
    steps.push_back({.name = "copy", .src = &src, .dst = &dst, .bytes = bytes});
  }
};

}  // namespace

struct VkModel::Impl {
  const vk::Context* ctx;
  Graph graph;
  bool fp16 = false;
  size_t elem = sizeof(float);       // bytes per stored element
  std::vector<vk::Buffer> boundary;  // fp16 mode: fp32 graph inputs, then outputs
  std::vector<ExecNode> exec;
  std::set<const vk::Pipeline*> pipelines;  // borrowed from the context: the ones this model uses
  std::vector<vk::Buffer> constants;        // per constant value, or a zero/dummy buffer
  std::vector<int> storage_of;              // value id -> buffer slot, -1 constant
  std::vector<vk::Buffer> pool;             // planned activation buffers
  std::vector<vk::Buffer*> buffer_of;       // value id -> buffer
  size_t activation_bytes = 0, unplanned_bytes = 0;
  StepList plan_steps;                        // the graph's commands, in order
  std::unique_ptr<vk::CommandStream> stream;  // plan_steps recorded once, for submit()

  const vk::Pipeline& pipeline(const std::string& shader, uint32_t buffers, uint32_t push,
                               std::vector<uint32_t> spec) {
    const vk::Pipeline& p = ctx->pipeline(
        {.shader = kernels::kernel_shader(
             "nn/" + shader + (fp16 && shader != "to_half" && shader != "to_float" ? "_f16" : "")),
         .num_buffers = buffers,
         .push_constant_bytes = push,
         .specialization = std::move(spec)});
    pipelines.insert(&p);
    return p;
  }

  vk::Buffer& make_const(std::span<const float> data) {
    constants.emplace_back(*ctx, std::max<size_t>(data.size() * elem, 4));
    upload(constants.back(), data);
    return constants.back();
  }
  void upload(vk::Buffer& b, std::span<const float> data) const {
    if (data.empty()) return;
    if (!fp16) {
      b.upload(data.data(), data.size_bytes());
      return;
    }
    std::vector<Eigen::half> h(data.begin(), data.end());
    b.upload(h.data(), h.size() * sizeof(Eigen::half));
  }

  void fuse(const VkModelOptions& options);
  void plan();
  void plan_commands();
  void plan_node(const ExecNode& e);
  const vk::Buffer& buf(int v) const { return *buffer_of[static_cast<size_t>(v)]; }
  // 1-D shaders loop over their elements (grid stride): a CPU driver pays per workgroup, so it
  // gets a few fat ones; a GPU gets one invocation per element up to 65535 workgroups.
  vk::Groups groups1d(int64_t count) const {
    const uint32_t cap = ctx->info().kind == vk::DeviceKind::kCpu ? 64 : 65535;
    return {
        std::max<uint32_t>(1, std::min<uint32_t>(cap, static_cast<uint32_t>((count + 255) / 256))),
        1, 1};
  }
  const Dims& shape(int v) const { return graph.value(v).shape; }
};

void VkModel::Impl::fuse(const VkModelOptions& options) {
  std::vector<int> readers(graph.values().size(), 0);
  for (const Node& n : graph.nodes())
    for (int v : n.inputs) ++readers[static_cast<size_t>(v)];
  for (int v : graph.outputs()) ++readers[static_cast<size_t>(v)];
  const auto& nodes = graph.nodes();
  for (size_t i = 0; i < nodes.size(); ++i) {
    ExecNode e{&nodes[i], nodes[i].output};
    const bool conv = nodes[i].op == Op::kConv || nodes[i].op == Op::kConvTranspose;
    if (options.fuse_activations && conv && i + 1 < nodes.size() && act_code(nodes[i + 1].op) &&
        nodes[i + 1].inputs[0] == nodes[i].output &&
        readers[static_cast<size_t>(nodes[i].output)] == 1) {
      e.fused = true;
      e.act = nodes[i + 1].op;
      e.act_attrs = nodes[i + 1].attrs;
      e.output = nodes[i + 1].output;
      ++i;
    }
    exec.push_back(e);
  }
}

void VkModel::Impl::plan() {
  const size_t nv = graph.values().size();
  storage_of.assign(nv, -1);
  std::vector<int> last_use(nv, -1);
  std::vector<bool> pinned(nv, false);  // graph inputs/outputs keep their own buffer
  for (int v : graph.inputs()) pinned[static_cast<size_t>(v)] = true;
  for (int v : graph.outputs()) pinned[static_cast<size_t>(v)] = true;
  // Reshape/Flatten alias their input: the root's lifetime covers every alias.
  std::vector<int> root(nv);
  for (size_t v = 0; v < nv; ++v) root[v] = static_cast<int>(v);
  for (const ExecNode& e : exec) {
    const int in_root = root[static_cast<size_t>(e.node->inputs[0])];
    if ((e.node->op == Op::kReshape || e.node->op == Op::kFlatten) &&
        !pinned[static_cast<size_t>(e.output)] && !graph.value(in_root).is_constant) {
      root[static_cast<size_t>(e.output)] = root[static_cast<size_t>(e.node->inputs[0])];
    }
  }
  for (size_t i = 0; i < exec.size(); ++i) {
    for (int v : exec[i].node->inputs)
      last_use[static_cast<size_t>(root[static_cast<size_t>(v)])] = static_cast<int>(i);
  }
  std::vector<size_t> sizes;
  std::vector<bool> busy;
  auto bytes = [&](int v) { return static_cast<size_t>(num_elements(shape(v))) * elem; };
  auto allocate = [&](int v) {
    const size_t need = bytes(v);
    unplanned_bytes += need;
    int best = -1;
    for (size_t s = 0; s < sizes.size(); ++s) {
      if (busy[s]) continue;
      // Smallest free buffer that fits, else the largest free one (grown).
      if (best < 0) {
        best = static_cast<int>(s);
        continue;
      }
      const size_t b = sizes[static_cast<size_t>(best)];
      const bool fits = sizes[s] >= need, best_fits = b >= need;
      if ((fits && (!best_fits || sizes[s] < b)) || (!fits && !best_fits && sizes[s] > b))
        best = static_cast<int>(s);
    }
    if (best < 0 || pinned[static_cast<size_t>(v)]) {
      sizes.push_back(need);
      busy.push_back(true);
      best = static_cast<int>(sizes.size()) - 1;
    }
    sizes[static_cast<size_t>(best)] = std::max(sizes[static_cast<size_t>(best)], need);
    busy[static_cast<size_t>(best)] = true;
    storage_of[static_cast<size_t>(v)] = best;
  };
  for (int v : graph.inputs()) allocate(v);
  for (size_t i = 0; i < exec.size(); ++i) {
    const int out = exec[i].output;
    if (root[static_cast<size_t>(out)] != out) {
      storage_of[static_cast<size_t>(out)] =
          storage_of[static_cast<size_t>(root[static_cast<size_t>(out)])];
    } else {
      allocate(out);
    }
    for (int v : exec[i].node->inputs) {
      const int r = root[static_cast<size_t>(v)];
      if (graph.value(r).is_constant || pinned[static_cast<size_t>(r)]) continue;
      if (last_use[static_cast<size_t>(r)] == static_cast<int>(i))
        busy[static_cast<size_t>(storage_of[static_cast<size_t>(r)])] = false;
    }
  }
  for (size_t s : sizes) {
    pool.emplace_back(*ctx, std::max<size_t>(s, 4));
    activation_bytes += s;
  }
  buffer_of.assign(nv, nullptr);
  constants.reserve(nv + 2 * exec.size());  // pointers into it must stay valid
  for (size_t v = 0; v < nv; ++v) {
    const Value& val = graph.values()[v];
    if (val.is_constant)
      buffer_of[v] = &make_const(val.data);
    else if (storage_of[v] >= 0)
      buffer_of[v] = &pool[static_cast<size_t>(storage_of[v])];
  }
}

void VkModel::Impl::plan_node(const ExecNode& e) {
  const Node& n = *e.node;
  const Attrs& a = n.attrs;
  StepList& s = plan_steps;
  const int x = n.inputs[0];
  const Dims& xs = shape(x);
  const Dims& ys = shape(e.output);
  const vk::Buffer& y = buf(e.output);
  const int64_t count = num_elements(ys);
  switch (n.op) {
    case Op::kConv:
    case Op::kConvTranspose: {
      const bool conv = n.op == Op::kConv;
      const uint32_t act = e.fused ? *act_code(e.act) : 0;
      const int64_t cog = ys[1] / a.group;
      // Register block of conv2d.glsl: output channels (within one group) x adjacent pixels.
      const uint32_t ocb = conv && cog % 4 == 0 ? 4 : 1;
      const uint32_t pxb = conv ? 4 : 1;
      std::vector<uint32_t> spec = {ocb, act, fbits(e.act_attrs.alpha), fbits(e.act_attrs.beta)};
      if (conv) spec.push_back(pxb);
      const vk::Pipeline& p = pipeline(conv ? "conv2d" : "conv_transpose", 4, 15 * 4, spec);
      const vk::Buffer& bias =
          n.inputs.size() > 2 ? buf(n.inputs[2])
                              : make_const(std::vector<float>(static_cast<size_t>(ys[1]), 0.f));
      const uint32_t push[15] = {u32(xs[1]),       u32(xs[2]),         u32(xs[3]),
                                 u32(ys[1]),       u32(ys[2]),         u32(ys[3]),
                                 u32(a.kernel[0]), u32(a.kernel[1]),   u32(a.stride[0]),
                                 u32(a.stride[1]), u32(a.dilation[0]), u32(a.dilation[1]),
                                 u32(a.pads[0]),   u32(a.pads[1]),     u32(a.group)};
      s.dispatch(p, {vk::in(buf(x)), vk::in(buf(n.inputs[1])), vk::in(bias), vk::out(y)},
                 {u32((ys[2] * ((ys[3] + pxb - 1) / pxb) + 63) / 64), u32((ys[1] + ocb - 1) / ocb),
                  u32(ys[0])},
                 push, sizeof(push), n.name);
      return;
    }
    case Op::kRelu:
    case Op::kClip:
    case Op::kLeakyRelu:
    case Op::kSigmoid:
    case Op::kSoftplus:
    case Op::kSqrt: {
      const vk::Pipeline& p =
          pipeline("unary", 2, 4, {*act_code(n.op), fbits(a.alpha), fbits(a.beta)});
      s.dispatch(p, {vk::in(buf(x)), vk::out(y)}, groups1d(count), u32(count), n.name);
      return;
    }
    case Op::kAdd:
    case Op::kSub:
    case Op::kMul:
    case Op::kDiv:
    case Op::kPow: {
      const Shape4 o = shape4(ys), sa = broadcast_strides(shape(x)),
                   sb = broadcast_strides(shape(n.inputs[1]));
      // Inputs of lower rank are aligned to the right: pad their strides the same way.
      const uint32_t push[13] = {u32(o[0]),  u32(o[1]),  u32(o[2]),  u32(o[3]),  u32(sa[0]),
                                 u32(sa[1]), u32(sa[2]), u32(sa[3]), u32(sb[0]), u32(sb[1]),
                                 u32(sb[2]), u32(sb[3]), u32(count)};
      const vk::Pipeline& p = pipeline("binary", 3, sizeof(push), {binary_code(n.op)});
      s.dispatch(p, {vk::in(buf(x)), vk::in(buf(n.inputs[1])), vk::out(y)}, groups1d(count), push,
                 sizeof(push), n.name);
      return;
    }
    case Op::kConcat: {
      const auto ax = static_cast<size_t>(a.axis);
      const int64_t outer = num_elements(Dims(ys.begin(), ys.begin() + a.axis));
      const int64_t inner = num_elements(Dims(ys.begin() + a.axis + 1, ys.end()));
      const vk::Pipeline& p = pipeline("strided_copy", 2, sizeof(Copy4), {});
      int64_t offset = 0;
      for (int v : n.inputs) {
        const int64_t len = shape(v)[ax] * inner;
        const Copy4 c{{1, 1, u32(outer), u32(len)},
                      {0, 0, u32(len), 1},
                      {0, 0, u32(ys[ax] * inner), 1},
                      0,
                      u32(offset),
                      u32(outer * len)};
        s.dispatch(p, {vk::in(buf(v)), vk::inout(y)}, groups1d(outer * len), c, n.name);
        offset += len;
      }
      return;
    }
    case Op::kTranspose:
    case Op::kSlice: {
      Shape4 st{};
      int64_t off = 0;
      if (n.op == Op::kTranspose) {
        st = transpose_strides(xs, a.ints);
      } else {
        const SliceMap m = slice_map(xs, a.starts, a.steps);
        st = m.strides;
        off = m.offset;
      }
      const Shape4 o = shape4(ys), ds = contiguous_strides(o);
      const Copy4 c{{u32(o[0]), u32(o[1]), u32(o[2]), u32(o[3])},
                    {u32(st[0]), u32(st[1]), u32(st[2]), u32(st[3])},
                    {u32(ds[0]), u32(ds[1]), u32(ds[2]), u32(ds[3])},
                    u32(off),
                    0,
                    u32(count)};
      s.dispatch(pipeline("strided_copy", 2, sizeof(Copy4), {}), {vk::in(buf(x)), vk::inout(y)},
                 groups1d(count), c, n.name);
      return;
    }
    case Op::kReshape:
    case Op::kFlatten:
      if (&buf(x) != &y) s.copy(buf(x), y, static_cast<size_t>(count) * elem);
      return;
    case Op::kResize: {
      const uint32_t mode = a.resize == ResizeMode::kNearest           ? 0
                            : a.resize == ResizeMode::kLinearHalfPixel ? 1
                                                                       : 2;
      const uint32_t push[5] = {u32(xs[0] * xs[1]), u32(xs[2]), u32(xs[3]), u32(ys[2]), u32(ys[3])};
      s.dispatch(pipeline("resize", 2, sizeof(push), {mode}), {vk::in(buf(x)), vk::out(y)},
                 groups1d(count), push, sizeof(push), n.name);
      return;
    }
    case Op::kMaxPool:
    case Op::kAveragePool: {
      const uint32_t push[11] = {u32(xs[0] * xs[1]), u32(xs[2]),       u32(xs[3]),
                                 u32(ys[2]),         u32(ys[3]),       u32(a.kernel[0]),
                                 u32(a.kernel[1]),   u32(a.stride[0]), u32(a.stride[1]),
                                 u32(a.pads[0]),     u32(a.pads[1])};
      s.dispatch(pipeline("pool", 2, sizeof(push),
                          {n.op == Op::kMaxPool ? 1u : 0u, a.count_include_pad ? 1u : 0u}),
                 {vk::in(buf(x)), vk::out(y)}, groups1d(count), push, sizeof(push), n.name);
      return;
    }
    case Op::kGlobalAveragePool:
    case Op::kReduceMean: {
      const Shape4 in4 = shape4(xs);
      const Shape4 keep =
          n.op == Op::kGlobalAveragePool ? Shape4{xs[0], xs[1], 1, 1} : reduced_shape4(xs, a.axes);
      const uint32_t push[9] = {u32(keep[0]), u32(keep[1]), u32(keep[2]), u32(keep[3]), u32(in4[0]),
                                u32(in4[1]),  u32(in4[2]),  u32(in4[3]),  u32(count)};
      // One workgroup per output element (shaders/common/nn/reduce_mean.glsl).
      const vk::Groups groups{static_cast<uint32_t>(std::min<int64_t>(count, 65535)), 1, 1};
      s.dispatch(pipeline("reduce_mean", 2, sizeof(push), {}), {vk::in(buf(x)), vk::out(y)}, groups,
                 push, sizeof(push), n.name);
      return;
    }
    case Op::kMatMul:
    case Op::kGemm: {
      const Dims& bs = shape(n.inputs[1]);
      uint32_t push[14];
      const int64_t m = ys[ys.size() - 2], nn = ys.back();
      int64_t k, batch = 1;
      const vk::Buffer* bias = nullptr;
      float alpha = 1, beta = 0;
      uint32_t scm = 0, scn = 0;
      int64_t sab, sam, sak, sbb, sbk, sbn;
      if (n.op == Op::kMatMul) {
        k = xs.back();
        batch = count / (m * nn);
        sab = m * k, sam = k, sak = 1;
        sbb = bs.size() == 2 ? 0 : k * nn, sbk = nn, sbn = 1;
      } else {
        k = a.trans_a ? xs[0] : xs[1];
        sab = 0;
        sam = a.trans_a ? 1 : xs[1], sak = a.trans_a ? xs[1] : 1;
        sbb = 0;
        sbk = a.trans_b ? 1 : bs[1], sbn = a.trans_b ? bs[1] : 1;
        alpha = a.alpha;
        if (n.inputs.size() > 2) {
          beta = a.beta;
          bias = &buf(n.inputs[2]);
          const Shape4 cs = broadcast_strides(shape(n.inputs[2]));
          scm = u32(cs[2]), scn = u32(cs[3]);
        }
      }
      if (!bias) bias = &make_const(std::vector<float>{0.f});
      const uint32_t vals[14] = {u32(m),   u32(nn),      u32(k),      u32(sab), u32(sam),
                                 u32(sak), u32(sbb),     u32(sbk),    u32(sbn), scm,
                                 scn,      fbits(alpha), fbits(beta), 0};
      std::copy(vals, vals + 14, push);
      s.dispatch(pipeline("matmul", 4, 13 * 4, {}),
                 {vk::in(buf(x)), vk::in(buf(n.inputs[1])), vk::in(*bias), vk::out(y)},
                 {u32((nn + 15) / 16), u32((m + 15) / 16), u32(batch)}, push, 13 * 4, n.name);
      return;
    }
    case Op::kSoftmax: {
      const auto ax = static_cast<size_t>(a.axis);
      const int64_t inner = num_elements(Dims(xs.begin() + a.axis + 1, xs.end()));
      const int64_t outer = count / (xs[ax] * inner);
      const uint32_t push[3] = {u32(outer), u32(xs[ax]), u32(inner)};
      s.dispatch(pipeline("softmax", 2, sizeof(push), {}), {vk::in(buf(x)), vk::out(y)},
                 groups1d(outer * inner), push, sizeof(push), n.name);
      return;
    }
    case Op::kLayerNorm: {
      const int64_t inner = num_elements(Dims(xs.begin() + a.axis, xs.end()));
      const vk::Buffer& bias =
          n.inputs.size() > 2 ? buf(n.inputs[2])
                              : make_const(std::vector<float>(static_cast<size_t>(inner), 0.f));
      const uint32_t push[3] = {u32(count / inner), u32(inner), fbits(a.epsilon)};
      s.dispatch(pipeline("layer_norm", 4, sizeof(push), {}),
                 {vk::in(buf(x)), vk::in(buf(n.inputs[1])), vk::in(bias), vk::out(y)},
                 groups1d(count / inner), push, sizeof(push), n.name);
      return;
    }
  }
}

void VkModel::Impl::plan_commands() {
  StepList& s = plan_steps;
  if (fp16) {
    boundary.reserve(graph.inputs().size() + graph.outputs().size());
    for (int v : graph.inputs()) {
      const auto n = num_elements(shape(v));
      boundary.emplace_back(*ctx, static_cast<size_t>(n) * sizeof(float));
      s.dispatch(pipeline("to_half", 2, 4, {}), {vk::in(boundary.back()), vk::out(buf(v))},
                 groups1d(n), u32(n), "input_to_half");
    }
  }
  for (const ExecNode& e : exec) plan_node(e);
  if (fp16) {
    for (int v : graph.outputs()) {
      const auto n = num_elements(shape(v));
      boundary.emplace_back(*ctx, static_cast<size_t>(n) * sizeof(float));
      s.dispatch(pipeline("to_float", 2, 4, {}), {vk::in(buf(v)), vk::out(boundary.back())},
                 groups1d(n), u32(n), "output_to_float");
    }
  }
}

VkModel::VkModel(const vk::Context& ctx, const Graph& graph, VkModelOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.ctx = &ctx;
  m.graph = graph;
  if (options.fp16_storage) {
    if (!ctx.info().fp16_storage) {
      throw Error("kernels::VkModel: fp16 storage requested but '" + ctx.info().name +
                  "' lacks storageBuffer16BitAccess; build the model with fp16_storage = false");
    }
    m.fp16 = true;
    m.elem = 2;
  }
  for (const Value& v : graph.values()) {
    if (num_elements(v.shape) >= (int64_t{1} << 31)) {
      throw Error("kernels::VkModel: tensor '" + v.name + "' " + to_string(v.shape) +
                  " has 2^31 or more elements; split the input");
    }
  }
  m.fuse(options);
  m.plan();
  m.plan_commands();
  m.stream = std::make_unique<vk::CommandStream>(ctx);
  record(*m.stream);
}

VkModel::~VkModel() = default;
VkModel::VkModel(VkModel&&) noexcept = default;
VkModel& VkModel::operator=(VkModel&&) noexcept = default;

vk::Buffer& VkModel::input_buffer(size_t i) {
  Impl& m = *impl_;
  if (m.fp16) return m.boundary.at(i);
  return *m.buffer_of[static_cast<size_t>(m.graph.inputs().at(i))];
}
vk::Buffer& VkModel::output_buffer(size_t i) {
  Impl& m = *impl_;
  if (m.fp16) return m.boundary.at(m.graph.inputs().size() + i);
  return *m.buffer_of[static_cast<size_t>(m.graph.outputs().at(i))];
}
void VkModel::fill_activations(float value) {
  Impl& m = *impl_;
  for (vk::Buffer& b : m.pool) m.upload(b, std::vector<float>(b.size_bytes() / m.elem, value));
  for (vk::Buffer& b : m.boundary) {
    const std::vector<float> v(b.size_bytes() / sizeof(float), value);
    b.upload(v.data(), v.size() * sizeof(float));
  }
}

void VkModel::record(vk::CommandStream& stream) const {
  for (const Step& step : impl_->plan_steps.steps) {
    if (step.pipeline) {
      stream.dispatch(*step.pipeline, step.bindings, step.groups, step.push.data(),
                      step.push.size() * sizeof(uint32_t), step.name);
    } else {
      stream.copy(*step.src, *step.dst, step.bytes);
    }
  }
}

void VkModel::submit() {
  impl_->stream->submit_and_wait();
}

std::vector<Tensor> VkModel::run(std::span<const Tensor> inputs) {
  const Graph& g = impl_->graph;
  if (inputs.size() != g.inputs().size()) {
    throw Error("kernels::VkModel::run: " + std::to_string(inputs.size()) +
                " inputs given, the graph has " + std::to_string(g.inputs().size()));
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    const Value& v = g.value(g.inputs()[i]);
    if (inputs[i].shape != v.shape ||
        inputs[i].data.size() != static_cast<size_t>(num_elements(v.shape))) {
      throw Error("kernels::VkModel::run: input '" + v.name + "' must have shape " +
                  to_string(v.shape) + ", got " + to_string(inputs[i].shape));
    }
    const_cast<vk::Buffer&>(input_buffer(i))
        .upload(inputs[i].data.data(), inputs[i].data.size() * sizeof(float));
  }
  submit();
  std::vector<Tensor> out;
  for (size_t i = 0; i < g.outputs().size(); ++i) {
    const Dims& s = g.value(g.outputs()[i]).shape;
    Tensor t{s, std::vector<float>(static_cast<size_t>(num_elements(s)))};
    output_buffer(i).download(t.data.data(), t.data.size() * sizeof(float));
    out.push_back(std::move(t));
  }
  return out;
}

size_t VkModel::num_dispatches() const {
  return impl_->stream->num_commands();
}
size_t VkModel::num_pipelines() const {
  return impl_->pipelines.size();
}
size_t VkModel::activation_bytes() const {
  return impl_->activation_bytes;
}
size_t VkModel::unplanned_activation_bytes() const {
  return impl_->unplanned_bytes;
}
std::vector<vk::DispatchTime> VkModel::timings() const {
  return impl_->stream->timings();
}

}  // namespace pensight::kernels
