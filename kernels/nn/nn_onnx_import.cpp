#include <onnx/onnx_pb.h>

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "core/error.h"
#include "core/file_bytes.h"
#include "kernels/nn/nn_onnx.h"

namespace pensight::kernels {
namespace {

const char* kSupported =
    "Conv, ConvTranspose, BatchNormalization, Relu, Clip, LeakyRelu, Sigmoid, Softplus, Sqrt, Add, "
    "Sub, Mul, Div, Pow, Concat, Resize, MaxPool, AveragePool, GlobalAveragePool, MatMul, Gemm, "
    "Softmax, Transpose, Reshape, Flatten, Slice, ReduceMean, LayerNormalization, Identity, "
    "Dropout, Cast, Constant";

// Raw tensor data as doubles (float, float16, double, int32, int64).
std::vector<double> tensor_values(const onnx::TensorProto& t) {
  std::vector<double> v;
  const std::string& raw = t.raw_data();
  auto from_raw = [&](auto tag) {
    using T = decltype(tag);
    const size_t n = raw.size() / sizeof(T);
    for (size_t i = 0; i < n; ++i) {
      T x;
      std::memcpy(&x, raw.data() + i * sizeof(T), sizeof(T));
      v.push_back(static_cast<double>(x));
    }
  };
  switch (t.data_type()) {
    case onnx::TensorProto::FLOAT:
      if (!raw.empty()) from_raw(float{});
      for (float x : t.float_data()) v.push_back(x);
      break;
    case onnx::TensorProto::DOUBLE:
      if (!raw.empty()) from_raw(double{});
      for (double x : t.double_data()) v.push_back(x);
      break;
    case onnx::TensorProto::INT64:
      if (!raw.empty()) from_raw(int64_t{});
      for (int64_t x : t.int64_data()) v.push_back(static_cast<double>(x));
      break;
    case onnx::TensorProto::INT32:
      if (!raw.empty()) from_raw(int32_t{});
      for (int32_t x : t.int32_data()) v.push_back(x);
      break;
    case onnx::TensorProto::FLOAT16: {
      auto half = [&](uint16_t bits) {
        Eigen::half h;
        h.x = bits;
        v.push_back(static_cast<double>(static_cast<float>(h)));
      };
      for (size_t i = 0; 2 * i + 1 < raw.size(); ++i) {
        uint16_t bits;
        std::memcpy(&bits, raw.data() + 2 * i, 2);
        half(bits);
      }
      for (int32_t x : t.int32_data()) half(static_cast<uint16_t>(x));
      break;
    }
    default:
      throw Error("onnx: initializer '" + t.name() + "' has data type " +
                  std::to_string(t.data_type()) +
                  "; only float, float16, double, int32 and int64 are supported");
  }
  if (t.has_data_location() && t.data_location() == onnx::TensorProto::EXTERNAL) {
    throw Error("onnx: initializer '" + t.name() +
                "' uses external data; save the model with all tensors embedded");
  }
  return v;
}

// A constant's dims and values agree: every dim >= 0, as many values as the dims' product (a
// scalar, with no dims, has one). Checked before any use, so no shape from the file indexes past
// its data.
void check_constant(const std::string& name, const Dims& dims, const std::vector<double>& values) {
  bool agree = true;
  size_t count = 1;
  for (const int64_t d : dims) {
    const auto u = static_cast<size_t>(d);
    agree = agree && d >= 0 && (u == 0 || count <= values.size() / u);
    if (!agree) break;
    count *= u;
  }
  if (!agree || count != values.size()) {
    throw Error("onnx: constant '" + name + "' has " + std::to_string(values.size()) +
                " values for its dims; the file is damaged or not an ONNX model");
  }
}

class Reader {
 public:
  Reader(const onnx::ModelProto& m, std::string what) : m_(m), what_(std::move(what)) {}

  Graph run() {
    for (const auto& op : m_.opset_import()) {
      if (op.domain().empty() || op.domain() == "ai.onnx") opset_ = op.version();
    }
    const auto& gp = m_.graph();
    for (const auto& t : gp.initializer()) {
      Dims shape(t.dims().begin(), t.dims().end());
      std::vector<double> values = tensor_values(t);
      check_constant(t.name(), shape, values);
      consts_[t.name()] = {shape, std::move(values)};
    }
    for (const auto& in : gp.input()) {
      if (consts_.count(in.name())) continue;
      Dims shape;
      for (const auto& d : in.type().tensor_type().shape().dim()) {
        if (!d.has_dim_value() || d.dim_value() <= 0) {
          throw Error("onnx: " + what_ + ": input '" + in.name() + "' has a dynamic dimension ('" +
                      d.dim_param() +
                      "'); hint: export with a fixed input size (e.g. torch.onnx.export without "
                      "dynamic_axes)");
        }
        shape.push_back(d.dim_value());
      }
      if (in.type().tensor_type().elem_type() != onnx::TensorProto::FLOAT) {
        throw Error("onnx: " + what_ + ": input '" + in.name() + "' is not float32");
      }
      ids_[in.name()] = g_.add_input(in.name(), shape);
    }
    plan_bn_folding();
    for (const auto& n : gp.node()) node(n);
    for (const auto& out : gp.output()) {
      const int v = id(out.name(), "graph output");
      g_.values()[static_cast<size_t>(v)].name = out.name();
      g_.mark_output(v);
    }
    return std::move(g_);
  }

 private:
  [[noreturn]] void fail(const onnx::NodeProto& n, const std::string& msg,
                         const std::string& hint = {}) {
    throw Error("onnx: " + what_ + ": op '" + n.op_type() + "' in node '" + n.name() + "': " + msg +
                (hint.empty() ? "" : "; hint: " + hint));
  }

  int id(const std::string& name, const std::string& role) {
    auto it = ids_.find(name);
    if (it != ids_.end()) return it->second;
    auto c = consts_.find(name);
    if (c != consts_.end()) {
      Tensor t{c->second.first, {}};
      for (double x : c->second.second) t.data.push_back(static_cast<float>(x));
      if (t.shape.empty()) t.shape = {1};
      return ids_[name] = g_.add_constant(name, std::move(t));
    }
    throw Error("onnx: " + what_ + ": " + role + " '" + name + "' is not produced by any node");
  }
  const std::vector<double>& const_input(const onnx::NodeProto& n, int i, const char* what) {
    if (n.input_size() <= i || n.input(i).empty()) fail(n, std::string("missing input ") + what);
    auto c = consts_.find(n.input(i));
    if (c == consts_.end()) {
      fail(n, std::string(what) + " '" + n.input(i) + "' is computed at run time",
           "only constant shapes are supported: export with static shapes and constant folding "
           "(onnxsim)");
    }
    return c->second.second;
  }
  // A shape or index value of a constant input as an integer (exact in a double to 2^53).
  int64_t integer(const onnx::NodeProto& n, double x, const char* what) {
    if (!(std::abs(x) <= 9007199254740992.0) || x != std::floor(x))
      fail(n, std::string(what) + " must be whole numbers");
    return static_cast<int64_t>(x);
  }
  double first_value(const onnx::NodeProto& n, int i, const char* what) {
    const auto& v = const_input(n, i, what);
    if (v.empty()) fail(n, std::string(what) + " is empty");
    return v[0];
  }
  static const onnx::AttributeProto* attr(const onnx::NodeProto& n, const char* name) {
    for (const auto& a : n.attribute())
      if (a.name() == name) return &a;
    return nullptr;
  }
  static int64_t attr_i(const onnx::NodeProto& n, const char* name, int64_t def) {
    const auto* a = attr(n, name);
    return a ? a->i() : def;
  }
  static float attr_f(const onnx::NodeProto& n, const char* name, float def) {
    const auto* a = attr(n, name);
    return a ? a->f() : def;
  }
  static std::string attr_s(const onnx::NodeProto& n, const char* name, const std::string& def) {
    const auto* a = attr(n, name);
    return a ? a->s() : def;
  }
  static std::vector<int64_t> attr_ints(const onnx::NodeProto& n, const char* name) {
    const auto* a = attr(n, name);
    return a ? std::vector<int64_t>(a->ints().begin(), a->ints().end()) : std::vector<int64_t>{};
  }
  // A 2-D op's spatial attribute: absent (empty) or `count` values in [lo, 65536] as int.
  std::vector<int> spatial_ints(const onnx::NodeProto& n, const char* name, size_t count, int lo) {
    const std::vector<int64_t> v = attr_ints(n, name);
    if (v.empty()) return {};
    if (v.size() != count)
      fail(n, std::string(name) + " must have " + std::to_string(count) + " values",
           "only 2-D (NCHW) convolution and pooling are supported");
    std::vector<int> out;
    for (const int64_t x : v) {
      if (x < lo || x > 65536) fail(n, std::string(name) + " value out of range");
      out.push_back(static_cast<int>(x));
    }
    return out;
  }

  // Conv -> BatchNormalization with constant weights and the Conv output read only by the BN:
  // the BN parameters go into new Conv weights and bias, and the BN becomes an alias.
  void plan_bn_folding() {
    const auto& gp = m_.graph();
    std::map<std::string, int> readers;
    for (const auto& n : gp.node())
      for (const auto& in : n.input()) ++readers[in];
    for (const auto& o : gp.output()) ++readers[o.name()];
    std::map<std::string, const onnx::NodeProto*> conv_of;
    for (const auto& n : gp.node()) {
      if (n.op_type() == "Conv" && n.input_size() >= 2 && n.output_size() >= 1 &&
          consts_.count(n.input(1)))
        conv_of[n.output(0)] = &n;
    }
    for (const auto& bn : gp.node()) {
      if (bn.op_type() != "BatchNormalization" || bn.input_size() != 5) continue;
      auto c = conv_of.find(bn.input(0));
      if (c == conv_of.end() || readers[bn.input(0)] != 1) continue;
      bool all_const = true;
      for (int i = 1; i < 5; ++i) all_const = all_const && consts_.count(bn.input(i));
      if (!all_const) continue;
      const onnx::NodeProto& conv = *c->second;
      auto w = consts_.at(conv.input(1));
      const auto& scale = consts_.at(bn.input(1)).second;
      const auto& shift = consts_.at(bn.input(2)).second;
      const auto& mean = consts_.at(bn.input(3)).second;
      const auto& var = consts_.at(bn.input(4)).second;
      const double eps = attr_f(bn, "epsilon", 1e-5f);
      if (w.first.empty() || w.first[0] <= 0) continue;  // the Conv node reports its weight
      const size_t cout = static_cast<size_t>(w.first[0]);
      const bool sizes_agree =
          scale.size() == cout && shift.size() == cout && mean.size() == cout && var.size() == cout;
      if (!sizes_agree || conv.output_size() < 1 || bn.output_size() < 1) continue;
      const size_t per = w.second.size() / cout;
      std::vector<double> bias(cout, 0.0);
      if (conv.input_size() > 2 && consts_.count(conv.input(2)))
        bias = consts_.at(conv.input(2)).second;
      if (bias.size() != cout) continue;
      for (size_t o = 0; o < cout; ++o) {
        const double s = scale[o] / std::sqrt(var[o] + eps);
        for (size_t k = 0; k < per; ++k) w.second[o * per + k] *= s;
        bias[o] = (bias[o] - mean[o]) * s + shift[o];
      }
      const std::string wn = conv.name() + "_bnfolded_w", bn_name = conv.name() + "_bnfolded_b";
      consts_[wn] = w;
      consts_[bn_name] = {{static_cast<int64_t>(cout)}, bias};
      folded_conv_[&conv] = {wn, bn_name};
      bn_alias_[bn.output(0)] = conv.output(0);
    }
  }

  void node(const onnx::NodeProto& n) {
    const std::string& op = n.op_type();
    if (!n.domain().empty() && n.domain() != "ai.onnx")
      fail(n, "custom domain '" + n.domain() + "'", std::string("supported ops: ") + kSupported);
    if (n.output_size() < 1) fail(n, "has no output");
    const std::string out = n.output(0);
    auto in = [&](int i) {
      if (i >= n.input_size()) fail(n, "missing input " + std::to_string(i + 1));
      return id(n.input(i), "input");
    };
    auto emit = [&](Op o, std::vector<int> inputs, Attrs a) {
      try {
        ids_[out] = g_.add(o, std::move(inputs), std::move(a), n.name().empty() ? out : n.name());
      } catch (const Error& e) {
        fail(n, e.what());
      }
    };
    Attrs a;
    if (op == "Constant") {
      const auto* v = attr(n, "value");
      if (!v) fail(n, "only the 'value' form is supported");
      Dims shape(v->t().dims().begin(), v->t().dims().end());
      std::vector<double> values = tensor_values(v->t());
      check_constant(out, shape, values);
      consts_[out] = {shape, std::move(values)};
      return;
    }
    if (op == "Identity" || op == "Dropout" ||
        (op == "Cast" && attr_i(n, "to", 1) == onnx::TensorProto::FLOAT)) {
      if (n.input_size() > 0 && consts_.count(n.input(0)))
        consts_[out] = consts_.at(n.input(0));
      else
        ids_[out] = in(0);
      return;
    }
    if (op == "BatchNormalization") {
      if (auto it = bn_alias_.find(out); it != bn_alias_.end()) {
        ids_[out] = ids_.at(it->second);
        return;
      }
      // Standalone BN: y = x * s + (beta - mean * s) per channel.
      const auto& scale = const_input(n, 1, "scale");
      const auto& shift = const_input(n, 2, "bias");
      const auto& mean = const_input(n, 3, "mean");
      const auto& var = const_input(n, 4, "var");
      const double eps = attr_f(n, "epsilon", 1e-5f);
      if (shift.size() != scale.size() || mean.size() != scale.size() || var.size() != scale.size())
        fail(n, "scale, bias, mean and var must have one value per channel");
      const auto c = static_cast<int64_t>(scale.size());
      Tensor s{{1, c, 1, 1}, {}}, b{{1, c, 1, 1}, {}};
      for (size_t i = 0; i < scale.size(); ++i) {
        const double k = scale[i] / std::sqrt(var[i] + eps);
        s.data.push_back(static_cast<float>(k));
        b.data.push_back(static_cast<float>(shift[i] - mean[i] * k));
      }
      const int sv = g_.add_constant(out + "_scale", s), bv = g_.add_constant(out + "_shift", b);
      int y = 0;
      try {
        y = g_.add(Op::kMul, {in(0), sv}, {}, n.name() + "_mul");
      } catch (const Error& e) {
        fail(n, e.what());
      }
      emit(Op::kAdd, {y, bv}, {});
      return;
    }
    if (op == "Conv" || op == "ConvTranspose") {
      if (attr_s(n, "auto_pad", "NOTSET") != "NOTSET")
        fail(n, "auto_pad is not supported", "export with explicit pads");
      const auto pads = spatial_ints(n, "pads", 4, 0), strides = spatial_ints(n, "strides", 2, 1),
                 dil = spatial_ints(n, "dilations", 2, 1);
      if (!pads.empty()) a.pads = {pads[0], pads[1], pads[2], pads[3]};
      if (!strides.empty()) a.stride = {strides[0], strides[1]};
      if (!dil.empty()) a.dilation = {dil[0], dil[1]};
      const int64_t group = attr_i(n, "group", 1);
      if (group < 1 || group > 65536) fail(n, "group out of range");
      a.group = static_cast<int>(group);
      const auto op_pad = spatial_ints(n, "output_padding", 2, 0);
      if (!op_pad.empty()) a.output_padding = {op_pad[0], op_pad[1]};
      if (!attr_ints(n, "output_shape").empty())
        fail(n, "output_shape is not supported", "give pads instead");
      std::vector<int> inputs;
      if (auto f = folded_conv_.find(&n); f != folded_conv_.end()) {
        inputs = {in(0), id(f->second.first, "weight"), id(f->second.second, "bias")};
      } else {
        for (int i = 0; i < n.input_size(); ++i)
          if (!n.input(i).empty()) inputs.push_back(in(i));
      }
      emit(op == "Conv" ? Op::kConv : Op::kConvTranspose, inputs, a);
      return;
    }
    static const std::map<std::string, Op> simple = {{"Relu", Op::kRelu},
                                                     {"Sigmoid", Op::kSigmoid},
                                                     {"Softplus", Op::kSoftplus},
                                                     {"Sqrt", Op::kSqrt},
                                                     {"Add", Op::kAdd},
                                                     {"Sub", Op::kSub},
                                                     {"Mul", Op::kMul},
                                                     {"Div", Op::kDiv},
                                                     {"Pow", Op::kPow},
                                                     {"MatMul", Op::kMatMul},
                                                     {"GlobalAveragePool", Op::kGlobalAveragePool}};
    if (auto s = simple.find(op); s != simple.end()) {
      std::vector<int> inputs;
      for (int i = 0; i < n.input_size(); ++i) inputs.push_back(in(i));
      emit(s->second, inputs, a);
      return;
    }
    if (op == "LeakyRelu") {
      a.alpha = attr_f(n, "alpha", 0.01f);
      emit(Op::kLeakyRelu, {in(0)}, a);
    } else if (op == "Clip") {
      a.alpha = opset_ < 11
                    ? attr_f(n, "min", -INFINITY)
                    : (n.input_size() > 1 && !n.input(1).empty() ? float(first_value(n, 1, "min"))
                                                                 : -INFINITY);
      a.beta = opset_ < 11
                   ? attr_f(n, "max", INFINITY)
                   : (n.input_size() > 2 && !n.input(2).empty() ? float(first_value(n, 2, "max"))
                                                                : INFINITY);
      emit(Op::kClip, {in(0)}, a);
    } else if (op == "Concat") {
      a.axis = static_cast<int>(attr_i(n, "axis", 1));
      std::vector<int> inputs;
      for (int i = 0; i < n.input_size(); ++i) inputs.push_back(in(i));
      emit(Op::kConcat, inputs, a);
    } else if (op == "Resize") {
      const std::string mode = attr_s(n, "mode", "nearest"),
                        coord = attr_s(n, "coordinate_transformation_mode", "half_pixel");
      if (mode == "nearest" && coord == "asymmetric" &&
          attr_s(n, "nearest_mode", "round_prefer_floor") == "floor") {
        a.resize = ResizeMode::kNearest;
      } else if (mode == "linear" && (coord == "half_pixel" || coord == "pytorch_half_pixel")) {
        a.resize = ResizeMode::kLinearHalfPixel;
      } else if (mode == "linear" && coord == "align_corners") {
        a.resize = ResizeMode::kLinearAlignCorners;
      } else {
        fail(n,
             "mode '" + mode + "' with coordinate_transformation_mode '" + coord +
                 "' is not supported",
             "use nearest+asymmetric+floor, or linear with half_pixel or align_corners");
      }
      const Dims& xs = g_.value(in(0)).shape;
      if (xs.size() != 4) fail(n, "input must be 4-D");
      if (n.input_size() > 3 && !n.input(3).empty()) {
        const auto& sz = const_input(n, 3, "sizes");
        if (sz.size() != 4) fail(n, "sizes must have 4 values (N, C, H, W)");
        a.sizes = {integer(n, sz[2], "sizes"), integer(n, sz[3], "sizes")};
      } else {
        const auto& sc = const_input(n, 2, "scales");
        if (sc.size() != 4 || sc[0] != 1 || sc[1] != 1) fail(n, "only H/W scaling is supported");
        a.sizes = {integer(n, std::floor(double(xs[2]) * sc[2]), "scaled sizes"),
                   integer(n, std::floor(double(xs[3]) * sc[3]), "scaled sizes")};
      }
      emit(Op::kResize, {in(0)}, a);
    } else if (op == "MaxPool" || op == "AveragePool") {
      if (attr_i(n, "ceil_mode", 0) != 0)
        fail(n, "ceil_mode=1 is not supported", "pad explicitly instead");
      if (attr_s(n, "auto_pad", "NOTSET") != "NOTSET")
        fail(n, "auto_pad is not supported", "export with explicit pads");
      for (int64_t d : attr_ints(n, "dilations"))
        if (d != 1) fail(n, "dilated pooling is not supported");
      const auto k = spatial_ints(n, "kernel_shape", 2, 1), s = spatial_ints(n, "strides", 2, 1),
                 p = spatial_ints(n, "pads", 4, 0);
      if (k.size() != 2) fail(n, "only 2-D pooling is supported");
      a.kernel = {k[0], k[1]};
      if (!s.empty()) a.stride = {s[0], s[1]};
      if (!p.empty()) a.pads = {p[0], p[1], p[2], p[3]};
      a.count_include_pad = attr_i(n, "count_include_pad", 0) != 0;
      if (n.output_size() > 1 && !n.output(1).empty())
        fail(n, "the Indices output is not supported");
      emit(op == "MaxPool" ? Op::kMaxPool : Op::kAveragePool, {in(0)}, a);
    } else if (op == "Gemm") {
      a.alpha = attr_f(n, "alpha", 1.f);
      a.beta = attr_f(n, "beta", 1.f);
      a.trans_a = attr_i(n, "transA", 0) != 0;
      a.trans_b = attr_i(n, "transB", 0) != 0;
      std::vector<int> inputs = {in(0), in(1)};
      if (n.input_size() > 2 && !n.input(2).empty()) inputs.push_back(in(2));
      emit(Op::kGemm, inputs, a);
    } else if (op == "Softmax") {
      const int rank = static_cast<int>(g_.value(in(0)).shape.size());
      const int64_t axis = attr_i(n, "axis", opset_ >= 13 ? -1 : 1);
      a.axis = axis < -rank || axis >= rank ? rank : static_cast<int>(axis);
      if (rank == 0) fail(n, "input must have at least one dimension");
      if (a.axis == rank) fail(n, "axis out of range");
      if (opset_ < 13 && (a.axis + rank) % rank != rank - 1)
        fail(n, "opset < 13 Softmax over several axes", "re-export with opset >= 13");
      emit(Op::kSoftmax, {in(0)}, a);
    } else if (op == "Transpose") {
      a.ints = attr_ints(n, "perm");
      emit(Op::kTranspose, {in(0)}, a);
    } else if (op == "Reshape") {
      for (double v : const_input(n, 1, "shape")) a.ints.push_back(integer(n, v, "shape"));
      emit(Op::kReshape, {in(0)}, a);
    } else if (op == "Flatten") {
      a.axis = static_cast<int>(attr_i(n, "axis", 1));
      emit(Op::kFlatten, {in(0)}, a);
    } else if (op == "Slice") {
      auto ints = [&](int i, const char* what) {
        std::vector<int64_t> v;
        if (n.input_size() > i && !n.input(i).empty())
          for (double x : const_input(n, i, what))
            v.push_back(x >= 9.2e18 ? INT64_MAX : x <= -9.2e18 ? INT64_MIN : integer(n, x, what));
        return v;
      };
      if (opset_ < 10) {
        a.starts = attr_ints(n, "starts");
        a.ends = attr_ints(n, "ends");
        a.axes = attr_ints(n, "axes");
      } else {
        a.starts = ints(1, "starts");
        a.ends = ints(2, "ends");
        a.axes = ints(3, "axes");
        a.steps = ints(4, "steps");
      }
      emit(Op::kSlice, {in(0)}, a);
    } else if (op == "ReduceMean") {
      a.axes = attr_ints(n, "axes");
      if (n.input_size() > 1 && !n.input(1).empty())
        for (double x : const_input(n, 1, "axes")) a.axes.push_back(integer(n, x, "axes"));
      a.keepdims = attr_i(n, "keepdims", 1) != 0;
      emit(Op::kReduceMean, {in(0)}, a);
    } else if (op == "LayerNormalization") {
      a.axis = static_cast<int>(attr_i(n, "axis", -1));
      a.epsilon = attr_f(n, "epsilon", 1e-5f);
      std::vector<int> inputs = {in(0), in(1)};
      if (n.input_size() > 2 && !n.input(2).empty()) inputs.push_back(in(2));
      emit(Op::kLayerNorm, inputs, a);
    } else {
      static const std::set<std::string> shape_ops = {
          "Shape",  "Gather", "Unsqueeze", "Squeeze", "ConstantOfShape",
          "Expand", "Range",  "NonZero",   "Where",   "Equal"};
      fail(n, "unsupported op",
           shape_ops.count(op) ? "this op computes shapes at run time: export with static shapes "
                                 "and constant folding "
                                 "(torch.onnx.export(..., do_constant_folding=True), then onnxsim)"
                               : std::string("supported ops: ") + kSupported);
    }
  }

  const onnx::ModelProto& m_;
  std::string what_;
  Graph g_;
  int64_t opset_ = 17;
  std::map<std::string, int> ids_;
  std::map<std::string, std::pair<Dims, std::vector<double>>> consts_;
  std::map<const onnx::NodeProto*, std::pair<std::string, std::string>> folded_conv_;
  std::map<std::string, std::string> bn_alias_;
};

}  // namespace

Graph import_onnx_bytes(const std::string& bytes, const std::string& what) {
  onnx::ModelProto model;
  if (!model.ParseFromString(bytes)) {
    throw Error("onnx: " + what + " is not an ONNX model (protobuf parse failed); check the file");
  }
  return Reader(model, what).run();
}

Graph import_onnx(const std::filesystem::path& file) {
  std::optional<std::string> bytes = read_file_bytes(file);
  if (!bytes) throw Error("onnx: cannot open '" + file.string() + "' (check the path)");
  return import_onnx_bytes(*bytes, "'" + file.string() + "'");
}

}  // namespace pensight::kernels
