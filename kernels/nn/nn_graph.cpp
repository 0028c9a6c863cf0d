#include <algorithm>
#include <numeric>

#include "core/error.h"
#include "kernels/nn/nn.h"

namespace pensight::kernels {

int64_t num_elements(const Dims& shape) {
  return std::accumulate(shape.begin(), shape.end(), int64_t{1}, std::multiplies<>());
}

std::string to_string(const Dims& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) {
    if (i) s += ',';
    s += std::to_string(shape[i]);
  }
  s += ']';
  return s;
}

const char* to_string(Op op) {
  switch (op) {
    case Op::kConv:
      return "Conv";
    case Op::kConvTranspose:
      return "ConvTranspose";
    case Op::kRelu:
      return "Relu";
    case Op::kClip:
      return "Clip";
    case Op::kLeakyRelu:
      return "LeakyRelu";
    case Op::kSigmoid:
      return "Sigmoid";
    case Op::kSoftplus:
      return "Softplus";
    case Op::kSqrt:
      return "Sqrt";
    case Op::kAdd:
      return "Add";
    case Op::kSub:
      return "Sub";
    case Op::kMul:
      return "Mul";
    case Op::kDiv:
      return "Div";
    case Op::kPow:
      return "Pow";
    case Op::kConcat:
      return "Concat";
    case Op::kResize:
      return "Resize";
    case Op::kMaxPool:
      return "MaxPool";
    case Op::kAveragePool:
      return "AveragePool";
    case Op::kGlobalAveragePool:
      return "GlobalAveragePool";
    case Op::kMatMul:
      return "MatMul";
    case Op::kGemm:
      return "Gemm";
    case Op::kSoftmax:
      return "Softmax";
    case Op::kTranspose:
      return "Transpose";
    case Op::kReshape:
      return "Reshape";
    case Op::kFlatten:
      return "Flatten";
    case Op::kSlice:
      return "Slice";
    case Op::kReduceMean:
      return "ReduceMean";
    case Op::kLayerNorm:
      return "LayerNormalization";
  }
  return "?";
}

int Graph::add_input(std::string name, Dims shape) {
  for (int64_t d : shape) {
    if (d <= 0) {
      throw Error("nn: input '" + name + "' has shape " + to_string(shape) +
                  "; only static positive dimensions are supported (fix the batch/size first)");
    }
  }
  values_.push_back({std::move(name), std::move(shape), false, {}});
  inputs_.push_back(static_cast<int>(values_.size()) - 1);
  return inputs_.back();
}

int Graph::add_constant(std::string name, Tensor t) {
  if (static_cast<int64_t>(t.data.size()) != num_elements(t.shape)) {
    throw Error("nn: constant '" + name + "' has " + std::to_string(t.data.size()) +
                " values for shape " + to_string(t.shape));
  }
  values_.push_back({std::move(name), std::move(t.shape), true, std::move(t.data)});
  return static_cast<int>(values_.size()) - 1;
}

void Graph::mark_output(int v) {
  value(v);
  outputs_.push_back(v);
}

namespace {

int norm_axis(int64_t axis, size_t rank, bool inclusive = false) {
  const auto r = static_cast<int64_t>(rank) + (inclusive ? 1 : 0);
  if (axis < -r || axis >= r) throw Error("axis " + std::to_string(axis) + " out of range");
  return static_cast<int>(axis < 0 ? axis + r : axis);
}

Dims broadcast(const Dims& a, const Dims& b) {
  const size_t r = std::max(a.size(), b.size());
  if (r > 4) throw Error("rank above 4 is not supported");
  Dims out(r);
  for (size_t i = 0; i < r; ++i) {
    const int64_t da = i + a.size() >= r ? a[i + a.size() - r] : 1;
    const int64_t db = i + b.size() >= r ? b[i + b.size() - r] : 1;
    if (da != db && da != 1 && db != 1) {
      throw Error("shapes " + to_string(a) + " and " + to_string(b) + " do not broadcast");
    }
    out[i] = std::max(da, db);
  }
  return out;
}

void need_rank(const Dims& s, size_t rank, const char* what) {
  if (s.size() != rank) {
    throw Error(std::string(what) + " must have rank " + std::to_string(rank) + ", got " +
                to_string(s));
  }
}

Dims infer(Op op, const std::vector<const Value*>& in, Attrs& a) {
  auto need_inputs = [&](size_t lo, size_t hi) {
    if (in.size() < lo || in.size() > hi) {
      throw Error("takes " + std::to_string(lo) + ".." + std::to_string(hi) + " inputs, got " +
                  std::to_string(in.size()));
    }
  };
  const Dims& x = in.empty() ? Dims{} : in[0]->shape;
  switch (op) {
    case Op::kConv:
    case Op::kConvTranspose: {
      need_inputs(2, 3);
      need_rank(x, 4, "input");
      const Dims& w = in[1]->shape;
      need_rank(w, 4, "weight");
      a.kernel = {static_cast<int>(w[2]), static_cast<int>(w[3])};
      const int64_t g = a.group;
      const bool conv = op == Op::kConv;
      const int64_t cin = conv ? w[1] * g : w[0];
      const int64_t cout = conv ? w[0] : w[1] * g;
      if (g < 1 || x[1] != cin || cout % g != 0) {
        throw Error("input " + to_string(x) + " does not fit weight " + to_string(w) +
                    " with group " + std::to_string(g));
      }
      if (in.size() == 3 && num_elements(in[2]->shape) != cout) {
        throw Error("bias " + to_string(in[2]->shape) + " must hold " + std::to_string(cout));
      }
      Dims out{x[0], cout, 0, 0};
      for (int i = 0; i < 2; ++i) {
        const int64_t pads = a.pads[i] + a.pads[i + 2];
        const int64_t ext = int64_t{a.dilation[i]} * (a.kernel[i] - 1) + 1;
        out[2 + i] = conv ? (x[2 + i] + pads - ext) / a.stride[i] + 1
                          : (x[2 + i] - 1) * a.stride[i] - pads + ext + a.output_padding[i];
        if (out[2 + i] <= 0 || a.stride[i] < 1 || a.dilation[i] < 1) {
          throw Error("kernel/stride/padding give an empty output from " + to_string(x));
        }
      }
      return out;
    }
    case Op::kRelu:
    case Op::kClip:
    case Op::kLeakyRelu:
    case Op::kSigmoid:
    case Op::kSoftplus:
    case Op::kSqrt:
      need_inputs(1, 1);
      return x;
    case Op::kAdd:
    case Op::kSub:
    case Op::kMul:
    case Op::kDiv:
    case Op::kPow:
      need_inputs(2, 2);
      return broadcast(x, in[1]->shape);
    case Op::kConcat: {
      need_inputs(1, 64);
      a.axis = norm_axis(a.axis, x.size());
      Dims out = x;
      for (size_t i = 1; i < in.size(); ++i) {
        const Dims& s = in[i]->shape;
        bool ok = s.size() == x.size();
        for (size_t d = 0; ok && d < s.size(); ++d) ok = d == size_t(a.axis) || s[d] == x[d];
        if (!ok)
          throw Error("input " + to_string(s) + " does not concatenate with " + to_string(x));
        out[static_cast<size_t>(a.axis)] += s[static_cast<size_t>(a.axis)];
      }
      return out;
    }
    case Op::kResize:
      need_inputs(1, 1);
      need_rank(x, 4, "input");
      if (a.sizes[0] <= 0 || a.sizes[1] <= 0) throw Error("output size must be positive");
      return {x[0], x[1], a.sizes[0], a.sizes[1]};
    case Op::kMaxPool:
    case Op::kAveragePool: {
      need_inputs(1, 1);
      need_rank(x, 4, "input");
      Dims out{x[0], x[1], 0, 0};
      for (int i = 0; i < 2; ++i) {
        out[2 + i] = (x[2 + i] + a.pads[i] + a.pads[i + 2] - a.kernel[i]) / a.stride[i] + 1;
        if (out[2 + i] <= 0) throw Error("pooling window larger than the input " + to_string(x));
      }
      return out;
    }
    case Op::kGlobalAveragePool:
      need_inputs(1, 1);
      need_rank(x, 4, "input");
      return {x[0], x[1], 1, 1};
    case Op::kMatMul: {
      need_inputs(2, 2);
      const Dims& b = in[1]->shape;
      if (x.size() < 2 || b.size() < 2 || x.size() > 4 || b.size() > 4 ||
          x.back() != b[b.size() - 2] ||
          (b.size() > 2 && !std::equal(b.begin(), b.end() - 2, x.begin(), x.end() - 2))) {
        throw Error(to_string(x) + " x " + to_string(b) +
                    " is not supported (B must be 2-D or share A's batch dimensions)");
      }
      Dims out = x;
      out.back() = b.back();
      return out;
    }
    case Op::kGemm: {
      need_inputs(2, 3);
      const Dims& b = in[1]->shape;
      need_rank(x, 2, "A");
      need_rank(b, 2, "B");
      const int64_t m = a.trans_a ? x[1] : x[0], k = a.trans_a ? x[0] : x[1];
      const int64_t kb = a.trans_b ? b[1] : b[0], n = a.trans_b ? b[0] : b[1];
      if (k != kb) throw Error("A " + to_string(x) + " and B " + to_string(b) + " do not multiply");
      if (in.size() == 3) {
        const Dims c = broadcast(in[2]->shape, {m, n});
        if (c != Dims{m, n}) throw Error("C does not broadcast to [M,N]");
      }
      return {m, n};
    }
    case Op::kSoftmax:
      need_inputs(1, 1);
      a.axis = norm_axis(a.axis, x.size());
      return x;
    case Op::kTranspose: {
      need_inputs(1, 1);
      if (a.ints.empty()) {
        for (size_t i = x.size(); i-- > 0;) a.ints.push_back(static_cast<int64_t>(i));
      }
      Dims out(x.size());
      std::vector<bool> seen(x.size());
      if (a.ints.size() != x.size() || x.size() > 4) throw Error("perm does not fit the rank");
      for (size_t i = 0; i < x.size(); ++i) {
        const int p = norm_axis(a.ints[i], x.size());
        if (seen[static_cast<size_t>(p)]) throw Error("perm repeats an axis");
        seen[static_cast<size_t>(p)] = true;
        out[i] = x[static_cast<size_t>(p)];
      }
      return out;
    }
    case Op::kReshape: {
      need_inputs(1, 1);
      Dims out = a.ints;
      int infer_at = -1;
      for (size_t i = 0; i < out.size(); ++i) {
        if (out[i] == 0) out[i] = x.at(i);
        if (out[i] == -1) {
          if (infer_at >= 0) throw Error("shape has two -1 entries");
          infer_at = static_cast<int>(i);
          out[i] = 1;
        }
      }
      if (infer_at >= 0) out[static_cast<size_t>(infer_at)] = num_elements(x) / num_elements(out);
      if (num_elements(out) != num_elements(x) || out.size() > 4) {
        throw Error("cannot reshape " + to_string(x) + " to " + to_string(a.ints));
      }
      a.ints = out;
      return out;
    }
    case Op::kFlatten: {
      need_inputs(1, 1);
      a.axis = norm_axis(a.axis, x.size(), true);
      const auto mid = x.begin() + a.axis;
      return {std::accumulate(x.begin(), mid, int64_t{1}, std::multiplies<>()),
              std::accumulate(mid, x.end(), int64_t{1}, std::multiplies<>())};
    }
    case Op::kSlice: {
      need_inputs(1, 1);
      if (x.size() > 4) throw Error("rank above 4 is not supported");
      std::vector<int64_t> starts(x.size(), 0), steps(x.size(), 1);
      Dims out = x;
      const size_t n = a.starts.size();
      if (a.ends.size() != n || (!a.axes.empty() && a.axes.size() != n) ||
          (!a.steps.empty() && a.steps.size() != n)) {
        throw Error("starts/ends/axes/steps lengths differ");
      }
      for (size_t i = 0; i < n; ++i) {
        const auto ax =
            static_cast<size_t>(norm_axis(a.axes.empty() ? int64_t(i) : a.axes[i], x.size()));
        const int64_t step = a.steps.empty() ? 1 : a.steps[i];
        if (step <= 0)
          throw Error(
              "only positive steps are supported (reverse with a Transpose/Gather-free graph)");
        const int64_t d = x[ax];
        auto clampi = [&](int64_t v) { return std::clamp(v < 0 ? v + d : v, int64_t{0}, d); };
        const int64_t s = clampi(a.starts[i]), e = clampi(a.ends[i]);
        starts[ax] = s;
        steps[ax] = step;
        out[ax] = e > s ? (e - s + step - 1) / step : 0;
        if (out[ax] == 0) throw Error("slice of axis " + std::to_string(ax) + " is empty");
      }
      a.starts = starts;
      a.steps = steps;
      a.ends.clear();
      a.axes.clear();
      return out;
    }
    case Op::kReduceMean: {
      need_inputs(1, 1);
      if (x.size() > 4) throw Error("rank above 4 is not supported");
      std::vector<int64_t> axes;
      for (int64_t ax : a.axes) axes.push_back(norm_axis(ax, x.size()));
      if (axes.empty()) {
        for (size_t i = 0; i < x.size(); ++i) axes.push_back(static_cast<int64_t>(i));
      }
      std::sort(axes.begin(), axes.end());
      a.axes = axes;
      Dims out;
      for (size_t i = 0; i < x.size(); ++i) {
        const bool reduced = std::find(axes.begin(), axes.end(), int64_t(i)) != axes.end();
        if (!reduced)
          out.push_back(x[i]);
        else if (a.keepdims)
          out.push_back(1);
      }
      return out;
    }
    case Op::kLayerNorm: {
      need_inputs(2, 3);
      a.axis = norm_axis(a.axis, x.size());
      const Dims inner(x.begin() + a.axis, x.end());
      for (size_t i = 1; i < in.size(); ++i) {
        if (num_elements(in[i]->shape) != num_elements(inner)) {
          throw Error("scale/bias " + to_string(in[i]->shape) + " must match " + to_string(inner));
        }
      }
      return x;
    }
  }
  throw Error("unknown op");
}

}  // namespace

int Graph::add(Op op, std::vector<int> inputs, Attrs attrs, std::string name) {
  if (name.empty()) name = std::string(to_string(op)) + "_" + std::to_string(nodes_.size());
  std::vector<const Value*> in;
  for (int v : inputs) {
    if (v < 0 || v >= static_cast<int>(values_.size())) {
      throw Error("nn: " + std::string(to_string(op)) + " node '" + name + "' reads value " +
                  std::to_string(v) + " that does not exist");
    }
    in.push_back(&values_[static_cast<size_t>(v)]);
  }
  Dims shape;
  try {
    shape = infer(op, in, attrs);
  } catch (const Error& e) {
    throw Error("nn: " + std::string(to_string(op)) + " node '" + name + "': " + e.what());
  }
  values_.push_back({name + ":out", std::move(shape), false, {}});
  nodes_.push_back({op, std::move(name), std::move(inputs), static_cast<int>(values_.size()) - 1,
                    std::move(attrs)});
  return nodes_.back().output;
}

double Graph::flops() const {
  double f = 0;
  for (const Node& n : nodes_) {
    const Dims& out = value(n.output).shape;
    const Dims& x = value(n.inputs[0]).shape;
    if (n.op == Op::kConv) {
      const Dims& w = value(n.inputs[1]).shape;
      f += 2.0 * static_cast<double>(num_elements(out) * w[1] * w[2] * w[3]);
    } else if (n.op == Op::kConvTranspose) {
      const Dims& w = value(n.inputs[1]).shape;
      f += 2.0 * static_cast<double>(num_elements(x) * w[1] * w[2] * w[3]);
    } else if (n.op == Op::kMatMul || n.op == Op::kGemm) {
      const int64_t k = n.op == Op::kGemm && n.attrs.trans_a ? x[0] : x.back();
      f += 2.0 * static_cast<double>(num_elements(out) * k);
    }
  }
  return f;
}

}  // namespace pensight::kernels
