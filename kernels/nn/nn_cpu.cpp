// CPU reference executor: straightforward loops in double where accuracy matters, Eigen GEMM for
// convolutions (im2col) and matrix products.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "kernels/nn/nn.h"
#include "kernels/nn/nn_detail.h"

namespace pensight::kernels {
namespace {

using RowMat = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MapM = Eigen::Map<RowMat>;
using CMapM = Eigen::Map<const RowMat>;

void conv(const Node& n, const Tensor& x, const Tensor& w, const Tensor* b, Tensor& y) {
  const Attrs& a = n.attrs;
  const int64_t batch = x.shape[0], cin = x.shape[1], h = x.shape[2], wd = x.shape[3];
  const int64_t cout = y.shape[1], oh = y.shape[2], ow = y.shape[3];
  const int64_t g = a.group, cig = cin / g, cog = cout / g, kh = a.kernel[0], kw = a.kernel[1];
  const int64_t kdim = cig * kh * kw;
  RowMat cols(kdim, oh * ow);
  for (int64_t bi = 0; bi < batch; ++bi) {
    for (int64_t gi = 0; gi < g; ++gi) {
      for (int64_t c = 0; c < cig; ++c) {
        const float* src = &x.data[static_cast<size_t>(((bi * cin) + gi * cig + c) * h * wd)];
        for (int64_t ky = 0; ky < kh; ++ky) {
          for (int64_t kx = 0; kx < kw; ++kx) {
            float* dst = &cols((c * kh + ky) * kw + kx, 0);
            for (int64_t oy = 0; oy < oh; ++oy) {
              const int64_t iy = oy * a.stride[0] - a.pads[0] + ky * a.dilation[0];
              for (int64_t ox = 0; ox < ow; ++ox) {
                const int64_t ix = ox * a.stride[1] - a.pads[1] + kx * a.dilation[1];
                dst[oy * ow + ox] =
                    iy >= 0 && iy < h && ix >= 0 && ix < wd ? src[iy * wd + ix] : 0.f;
              }
            }
          }
        }
      }
      const CMapM wg(&w.data[static_cast<size_t>(gi * cog * kdim)], cog, kdim);
      MapM yg(&y.data[static_cast<size_t>((bi * cout + gi * cog) * oh * ow)], cog, oh * ow);
      yg.noalias() = wg * cols;
      if (b) {
        for (int64_t o = 0; o < cog; ++o)
          yg.row(o).array() += b->data[static_cast<size_t>(gi * cog + o)];
      }
    }
  }
}

void conv_transpose(const Node& n, const Tensor& x, const Tensor& w, const Tensor* b, Tensor& y) {
  const Attrs& a = n.attrs;
  const int64_t batch = x.shape[0], cin = x.shape[1], h = x.shape[2], wd = x.shape[3];
  const int64_t cout = y.shape[1], oh = y.shape[2], ow = y.shape[3];
  const int64_t g = a.group, cig = cin / g, cog = cout / g, kh = a.kernel[0], kw = a.kernel[1];
  std::vector<double> acc(y.data.size(), 0.0);
  for (int64_t bi = 0; bi < batch; ++bi) {
    for (int64_t ci = 0; ci < cin; ++ci) {
      const int64_t gi = ci / cig;
      for (int64_t co = 0; co < cog; ++co) {
        for (int64_t ky = 0; ky < kh; ++ky) {
          for (int64_t kx = 0; kx < kw; ++kx) {
            const float wv = w.data[static_cast<size_t>(((ci * cog + co) * kh + ky) * kw + kx)];
            for (int64_t iy = 0; iy < h; ++iy) {
              const int64_t oy = iy * a.stride[0] - a.pads[0] + ky * a.dilation[0];
              if (oy < 0 || oy >= oh) continue;
              for (int64_t ix = 0; ix < wd; ++ix) {
                const int64_t ox = ix * a.stride[1] - a.pads[1] + kx * a.dilation[1];
                if (ox < 0 || ox >= ow) continue;
                acc[static_cast<size_t>(((bi * cout + gi * cog + co) * oh + oy) * ow + ox)] +=
                    double{wv} * x.data[static_cast<size_t>(((bi * cin + ci) * h + iy) * wd + ix)];
              }
            }
          }
        }
      }
    }
  }
  for (size_t i = 0; i < acc.size(); ++i) {
    const int64_t c = static_cast<int64_t>(i) / (oh * ow) % cout;
    y.data[i] = static_cast<float>(acc[i]) + (b ? b->data[static_cast<size_t>(c)] : 0.f);
  }
}

void binary(Op op, const Tensor& x0, const Tensor& x1, Tensor& y) {
  const Shape4 o = shape4(y.shape), sa = broadcast_strides(x0.shape),
               sb = broadcast_strides(x1.shape);
  size_t i = 0;
  for (int64_t d0 = 0; d0 < o[0]; ++d0)
    for (int64_t d1 = 0; d1 < o[1]; ++d1)
      for (int64_t d2 = 0; d2 < o[2]; ++d2)
        for (int64_t d3 = 0; d3 < o[3]; ++d3, ++i) {
          const float p =
              x0.data[static_cast<size_t>(d0 * sa[0] + d1 * sa[1] + d2 * sa[2] + d3 * sa[3])];
          const float q =
              x1.data[static_cast<size_t>(d0 * sb[0] + d1 * sb[1] + d2 * sb[2] + d3 * sb[3])];
          y.data[i] = apply_binary(op, p, q);
        }
}

void concat(const Node& n, const std::vector<const Tensor*>& in, Tensor& y) {
  const auto ax = static_cast<size_t>(n.attrs.axis);
  const int64_t outer = num_elements(Dims(y.shape.begin(), y.shape.begin() + n.attrs.axis));
  const int64_t inner = num_elements(Dims(y.shape.begin() + n.attrs.axis + 1, y.shape.end()));
  int64_t offset = 0;
  for (const Tensor* t : in) {
    const int64_t len = t->shape[ax] * inner;
    for (int64_t o = 0; o < outer; ++o) {
      std::copy_n(&t->data[static_cast<size_t>(o * len)], len,
                  &y.data[static_cast<size_t>(o * y.shape[ax] * inner + offset)]);
    }
    offset += len;
  }
}

void resize(const Node& n, const Tensor& x, Tensor& y) {
  const int64_t nc = x.shape[0] * x.shape[1], h = x.shape[2], w = x.shape[3];
  const int64_t oh = y.shape[2], ow = y.shape[3];
  size_t i = 0;
  for (int64_t p = 0; p < nc; ++p) {
    const float* src = &x.data[static_cast<size_t>(p * h * w)];
    for (int64_t oy = 0; oy < oh; ++oy) {
      for (int64_t ox = 0; ox < ow; ++ox, ++i) {
        if (n.attrs.resize == ResizeMode::kNearest) {
          y.data[i] = src[nearest_src(oy, h, oh) * w + nearest_src(ox, w, ow)];
          continue;
        }
        const LinearTap ty = linear_src(n.attrs.resize, oy, h, oh);
        const LinearTap tx = linear_src(n.attrs.resize, ox, w, ow);
        const float top = src[ty.i0 * w + tx.i0] * (1 - tx.f) + src[ty.i0 * w + tx.i1] * tx.f;
        const float bot = src[ty.i1 * w + tx.i0] * (1 - tx.f) + src[ty.i1 * w + tx.i1] * tx.f;
        y.data[i] = top * (1 - ty.f) + bot * ty.f;
      }
    }
  }
}

void pool(const Node& n, const Tensor& x, Tensor& y) {
  const Attrs& a = n.attrs;
  const int64_t nc = x.shape[0] * x.shape[1], h = x.shape[2], w = x.shape[3];
  const int64_t oh = y.shape[2], ow = y.shape[3];
  const bool is_max = n.op == Op::kMaxPool;
  size_t i = 0;
  for (int64_t p = 0; p < nc; ++p) {
    const float* src = &x.data[static_cast<size_t>(p * h * w)];
    for (int64_t oy = 0; oy < oh; ++oy) {
      for (int64_t ox = 0; ox < ow; ++ox, ++i) {
        double acc = is_max ? -INFINITY : 0.0;
        int count = 0;
        for (int ky = 0; ky < a.kernel[0]; ++ky) {
          for (int kx = 0; kx < a.kernel[1]; ++kx) {
            const int64_t iy = oy * a.stride[0] - a.pads[0] + ky,
                          ix = ox * a.stride[1] - a.pads[1] + kx;
            if (iy < 0 || iy >= h || ix < 0 || ix >= w) continue;
            const float v = src[iy * w + ix];
            acc = is_max ? std::max(acc, double{v}) : acc + v;
            ++count;
          }
        }
        const int div = a.count_include_pad ? a.kernel[0] * a.kernel[1] : count;
        y.data[i] = static_cast<float>(is_max ? acc : acc / div);
      }
    }
  }
}

void matmul(const Tensor& x0, const Tensor& x1, Tensor& y) {
  const int64_t m = x0.shape[x0.shape.size() - 2], k = x0.shape.back(), n = x1.shape.back();
  const int64_t batch = num_elements(x0.shape) / (m * k);
  const bool shared_b = x1.shape.size() == 2;
  for (int64_t b = 0; b < batch; ++b) {
    const CMapM A(&x0.data[static_cast<size_t>(b * m * k)], m, k);
    const CMapM B(&x1.data[static_cast<size_t>(shared_b ? 0 : b * k * n)], k, n);
    MapM(&y.data[static_cast<size_t>(b * m * n)], m, n).noalias() = A * B;
  }
}

void gemm(const Node& node, const Tensor& x0, const Tensor& x1, const Tensor* c, Tensor& y) {
  const Attrs& a = node.attrs;
  const CMapM A(x0.data.data(), x0.shape[0], x0.shape[1]);
  const CMapM B(x1.data.data(), x1.shape[0], x1.shape[1]);
  MapM Y(y.data.data(), y.shape[0], y.shape[1]);
  if (a.trans_a && a.trans_b)
    Y.noalias() = A.transpose() * B.transpose();
  else if (a.trans_a)
    Y.noalias() = A.transpose() * B;
  else if (a.trans_b)
    Y.noalias() = A * B.transpose();
  else
    Y.noalias() = A * B;
  Y *= a.alpha;
  if (c) {
    Tensor cb{y.shape, std::vector<float>(y.data.size())};
    Tensor zero{{1}, {0.f}};
    binary(Op::kAdd, *c, zero, cb);
    for (size_t i = 0; i < y.data.size(); ++i) y.data[i] += a.beta * cb.data[i];
  }
}

void softmax(const Node& n, const Tensor& x, Tensor& y) {
  const auto ax = static_cast<size_t>(n.attrs.axis);
  const int64_t len = x.shape[ax];
  const int64_t inner = num_elements(Dims(x.shape.begin() + n.attrs.axis + 1, x.shape.end()));
  const int64_t outer = num_elements(x.shape) / (len * inner);
  for (int64_t o = 0; o < outer; ++o) {
    for (int64_t in = 0; in < inner; ++in) {
      const size_t base = static_cast<size_t>(o * len * inner + in);
      float mx = -INFINITY;
      for (int64_t k = 0; k < len; ++k)
        mx = std::max(mx, x.data[base + static_cast<size_t>(k * inner)]);
      double sum = 0;
      for (int64_t k = 0; k < len; ++k)
        sum += std::exp(double{x.data[base + static_cast<size_t>(k * inner)]} - mx);
      for (int64_t k = 0; k < len; ++k) {
        const size_t j = base + static_cast<size_t>(k * inner);
        y.data[j] = static_cast<float>(std::exp(double{x.data[j]} - mx) / sum);
      }
    }
  }
}

// Transpose and Slice: out[d] = in[sum d_i * stride_i + offset].
void gather4(const Tensor& x, const Shape4& in_strides, int64_t offset, Tensor& y) {
  const Shape4 o = shape4(y.shape);
  size_t i = 0;
  for (int64_t d0 = 0; d0 < o[0]; ++d0)
    for (int64_t d1 = 0; d1 < o[1]; ++d1)
      for (int64_t d2 = 0; d2 < o[2]; ++d2)
        for (int64_t d3 = 0; d3 < o[3]; ++d3, ++i) {
          y.data[i] = x.data[static_cast<size_t>(offset + d0 * in_strides[0] + d1 * in_strides[1] +
                                                 d2 * in_strides[2] + d3 * in_strides[3])];
        }
}

void reduce_mean(const Node& n, const Tensor& x, Tensor& y) {
  const Shape4 xs = shape4(x.shape);
  const Shape4 keep = reduced_shape4(x.shape, n.attrs.axes);
  const Shape4 ys = contiguous_strides(keep);
  std::vector<double> acc(y.data.size(), 0.0);
  size_t i = 0;
  for (int64_t d0 = 0; d0 < xs[0]; ++d0)
    for (int64_t d1 = 0; d1 < xs[1]; ++d1)
      for (int64_t d2 = 0; d2 < xs[2]; ++d2)
        for (int64_t d3 = 0; d3 < xs[3]; ++d3, ++i) {
          const int64_t j = (keep[0] > 1 ? d0 : 0) * ys[0] + (keep[1] > 1 ? d1 : 0) * ys[1] +
                            (keep[2] > 1 ? d2 : 0) * ys[2] + (keep[3] > 1 ? d3 : 0) * ys[3];
          acc[static_cast<size_t>(j)] += x.data[i];
        }
  const double count = static_cast<double>(x.data.size() / y.data.size());
  for (size_t j = 0; j < acc.size(); ++j) y.data[j] = static_cast<float>(acc[j] / count);
}

void layer_norm(const Node& n, const Tensor& x, const Tensor& scale, const Tensor* bias,
                Tensor& y) {
  const int64_t inner = num_elements(Dims(x.shape.begin() + n.attrs.axis, x.shape.end()));
  const int64_t rows = num_elements(x.shape) / inner;
  for (int64_t r = 0; r < rows; ++r) {
    const float* src = &x.data[static_cast<size_t>(r * inner)];
    double mean = 0, var = 0;
    for (int64_t k = 0; k < inner; ++k) mean += src[k];
    mean /= static_cast<double>(inner);
    for (int64_t k = 0; k < inner; ++k) var += (src[k] - mean) * (src[k] - mean);
    var /= static_cast<double>(inner);
    const double inv = 1.0 / std::sqrt(var + n.attrs.epsilon);
    for (int64_t k = 0; k < inner; ++k) {
      const auto kk = static_cast<size_t>(k);
      y.data[static_cast<size_t>(r * inner) + kk] = static_cast<float>(
          (src[k] - mean) * inv * scale.data[kk] + (bias ? bias->data[kk] : 0.f));
    }
  }
}

}  // namespace

std::vector<Tensor> run_cpu(const Graph& g, std::span<const Tensor> inputs) {
  if (inputs.size() != g.inputs().size()) {
    throw Error("kernels::run_cpu: " + std::to_string(inputs.size()) +
                " inputs given, the graph has " + std::to_string(g.inputs().size()));
  }
  std::vector<Tensor> vals(g.values().size());
  for (size_t i = 0; i < g.values().size(); ++i) {
    if (g.values()[i].is_constant) vals[i] = {g.values()[i].shape, g.values()[i].data};
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    const Value& v = g.value(g.inputs()[i]);
    if (inputs[i].shape != v.shape ||
        inputs[i].data.size() != static_cast<size_t>(num_elements(v.shape))) {
      throw Error("kernels::run_cpu: input '" + v.name + "' must have shape " + to_string(v.shape) +
                  ", got " + to_string(inputs[i].shape));
    }
    vals[static_cast<size_t>(g.inputs()[i])] = inputs[i];
  }
  for (const Node& n : g.nodes()) {
    std::vector<const Tensor*> in;
    for (int v : n.inputs) in.push_back(&vals[static_cast<size_t>(v)]);
    Tensor& y = vals[static_cast<size_t>(n.output)];
    y.shape = g.value(n.output).shape;
    y.data.assign(static_cast<size_t>(num_elements(y.shape)), 0.f);
    const Tensor* third = in.size() > 2 ? in[2] : nullptr;
    switch (n.op) {
      case Op::kConv:
        conv(n, *in[0], *in[1], third, y);
        break;
      case Op::kConvTranspose:
        conv_transpose(n, *in[0], *in[1], third, y);
        break;
      case Op::kRelu:
      case Op::kClip:
      case Op::kLeakyRelu:
      case Op::kSigmoid:
      case Op::kSoftplus:
      case Op::kSqrt:
        for (size_t i = 0; i < y.data.size(); ++i)
          y.data[i] = apply_unary(n.op, n.attrs, in[0]->data[i]);
        break;
      case Op::kAdd:
      case Op::kSub:
      case Op::kMul:
      case Op::kDiv:
      case Op::kPow:
        binary(n.op, *in[0], *in[1], y);
        break;
      case Op::kConcat:
        concat(n, in, y);
        break;
      case Op::kResize:
        resize(n, *in[0], y);
        break;
      case Op::kMaxPool:
      case Op::kAveragePool:
        pool(n, *in[0], y);
        break;
      case Op::kGlobalAveragePool: {
        const size_t hw = static_cast<size_t>(in[0]->shape[2] * in[0]->shape[3]);
        for (size_t p = 0; p < y.data.size(); ++p) {
          double s = 0;
          for (size_t k = 0; k < hw; ++k) s += in[0]->data[p * hw + k];
          y.data[p] = static_cast<float>(s / static_cast<double>(hw));
        }
        break;
      }
      case Op::kMatMul:
        matmul(*in[0], *in[1], y);
        break;
      case Op::kGemm:
        gemm(n, *in[0], *in[1], third, y);
        break;
      case Op::kSoftmax:
        softmax(n, *in[0], y);
        break;
      case Op::kTranspose:
        gather4(*in[0], transpose_strides(in[0]->shape, n.attrs.ints), 0, y);
        break;
      case Op::kReshape:
      case Op::kFlatten:
        y.data = in[0]->data;
        break;
      case Op::kSlice: {
        const SliceMap s = slice_map(in[0]->shape, n.attrs.starts, n.attrs.steps);
        gather4(*in[0], s.strides, s.offset, y);
        break;
      }
      case Op::kReduceMean:
        reduce_mean(n, *in[0], y);
        break;
      case Op::kLayerNorm:
        layer_norm(n, *in[0], *in[1], third, y);
        break;
    }
  }
  std::vector<Tensor> out;
  for (int v : g.outputs()) out.push_back(vals[static_cast<size_t>(v)]);
  return out;
}

}  // namespace pensight::kernels
