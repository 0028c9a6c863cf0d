#pragma once
// Random tensors and output comparison for the nn engine tests.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/nn/nn.h"

namespace pensight::kernels::testutil {

inline Tensor random_tensor(Dims shape, std::mt19937_64& rng, float lo = -1, float hi = 1) {
  std::uniform_real_distribution<float> u(lo, hi);
  Tensor t{std::move(shape), {}};
  t.data.resize(static_cast<size_t>(num_elements(t.shape)));
  for (float& v : t.data) v = u(rng);
  return t;
}

// Relative L2 error of `got` against `want`; NaN or a shape mismatch gives infinity.
inline double relative_l2(const Tensor& got, const Tensor& want) {
  if (got.shape != want.shape || got.data.size() != want.data.size()) return INFINITY;
  double num = 0, den = 0;
  for (size_t i = 0; i < got.data.size(); ++i) {
    if (!std::isfinite(got.data[i])) return INFINITY;
    num += std::pow(double{got.data[i]} - want.data[i], 2);
    den += std::pow(double{want.data[i]}, 2);
  }
  return std::sqrt(num / std::max(den, 1e-30));
}

// Elementwise |got - want| <= tol * (1 + |want|); NaN fails.
inline void expect_close(const Tensor& got, const Tensor& want, float tol = 1e-4f) {
  ASSERT_EQ(to_string(got.shape), to_string(want.shape));
  size_t bad = 0;
  for (size_t i = 0; i < want.data.size(); ++i) {
    if (!(std::abs(got.data[i] - want.data[i]) <= tol * (1 + std::abs(want.data[i])))) {
      if (++bad <= 5)
        ADD_FAILURE() << "element " << i << ": got " << got.data[i] << ", want " << want.data[i];
    }
  }
  EXPECT_EQ(bad, 0u) << "of " << want.data.size();
}

}  // namespace pensight::kernels::testutil
