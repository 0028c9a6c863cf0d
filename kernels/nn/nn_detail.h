#pragma once
// Index arithmetic and scalar op definitions shared by the CPU reference and the Vulkan host code
// (the shaders implement the same formulas).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/nn/nn.h"

namespace pensight::kernels {

using Shape4 = std::array<int64_t, 4>;

// Rank <= 4 shape padded with leading 1s.
inline Shape4 shape4(const Dims& d) {
  Shape4 s{1, 1, 1, 1};
  std::copy(d.begin(), d.end(), s.end() - static_cast<std::ptrdiff_t>(d.size()));
  return s;
}
inline Shape4 contiguous_strides(const Shape4& s) {
  return {s[1] * s[2] * s[3], s[2] * s[3], s[3], 1};
}
// Strides of `in` indexed by the 4-D position in `out` (0 along broadcast dimensions).
inline Shape4 broadcast_strides(const Dims& in) {
  const Shape4 s = shape4(in), st = contiguous_strides(s);
  Shape4 r{};
  for (size_t i = 0; i < 4; ++i) r[i] = s[i] == 1 ? 0 : st[i];
  return r;
}
// Input strides for each output dimension of a transpose (padded to 4-D).
inline Shape4 transpose_strides(const Dims& in, const std::vector<int64_t>& perm) {
  const size_t pad = 4 - in.size();
  const Shape4 st = contiguous_strides(shape4(in));
  Shape4 r{0, 0, 0, 0};
  for (size_t i = 0; i < perm.size(); ++i) r[pad + i] = st[pad + static_cast<size_t>(perm[i])];
  return r;
}
struct SliceMap {
  Shape4 strides;
  int64_t offset = 0;
};
inline SliceMap slice_map(const Dims& in, const std::vector<int64_t>& starts,
                          const std::vector<int64_t>& steps) {
  const size_t pad = 4 - in.size();
  const Shape4 st = contiguous_strides(shape4(in));
  SliceMap m{st, 0};
  for (size_t i = 0; i < in.size(); ++i) {
    m.strides[pad + i] = st[pad + i] * steps[i];
    m.offset += starts[i] * st[pad + i];
  }
  return m;
}
// 4-D shape of `in` with the reduced axes set to 1.
inline Shape4 reduced_shape4(const Dims& in, const std::vector<int64_t>& axes) {
  Shape4 s = shape4(in);
  for (int64_t a : axes) s[4 - in.size() + static_cast<size_t>(a)] = 1;
  return s;
}

inline float apply_unary(Op op, const Attrs& a, float x) {
  switch (op) {
    case Op::kRelu:
      return x > 0 ? x : 0.f;
    case Op::kClip:
      return std::min(std::max(x, a.alpha), a.beta);
    case Op::kLeakyRelu:
      return x >= 0 ? x : a.alpha * x;
    case Op::kSigmoid:
      return 1.f / (1.f + std::exp(-x));
    case Op::kSoftplus:
      return x > 20.f ? x : std::log1p(std::exp(x));
    case Op::kSqrt:
      return std::sqrt(x);
    default:
      return x;
  }
}
inline float apply_binary(Op op, float p, float q) {
  switch (op) {
    case Op::kAdd:
      return p + q;
    case Op::kSub:
      return p - q;
    case Op::kMul:
      return p * q;
    case Op::kDiv:
      return p / q;
    case Op::kPow:
      return q == 2.f ? p * p : std::pow(p, q);
    default:
      return p;
  }
}

// Resize, nearest: ONNX coordinate_transformation_mode=asymmetric, nearest_mode=floor.
inline int64_t nearest_src(int64_t o, int64_t in, int64_t out) {
  return std::min(
      in - 1, static_cast<int64_t>(std::floor(static_cast<float>(o) *
                                              (static_cast<float>(in) / static_cast<float>(out)))));
}
struct LinearTap {
  int64_t i0 = 0, i1 = 0;
  float f = 0;
};
// Resize, linear: source coordinate clamped to [0, in - 1] (as ONNX Runtime and PyTorch do).
inline LinearTap linear_src(ResizeMode mode, int64_t o, int64_t in, int64_t out) {
  float x;
  if (mode == ResizeMode::kLinearAlignCorners) {
    x = out > 1 ? static_cast<float>(o) * (static_cast<float>(in - 1) / static_cast<float>(out - 1))
                : 0.f;
  } else {
    x = (static_cast<float>(o) + 0.5f) * (static_cast<float>(in) / static_cast<float>(out)) - 0.5f;
  }
  x = std::clamp(x, 0.f, static_cast<float>(in - 1));
  const auto i0 = static_cast<int64_t>(std::floor(x));
  return {i0, std::min(i0 + 1, in - 1), x - static_cast<float>(i0)};
}

}  // namespace pensight::kernels
