#pragma once
// Shared by the CPU paths of sparse_prior (not part of the public interface).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "kernels/sparse_prior/sparse_prior.h"

namespace pensight::kernels {

// Keeps every int64 product of the exact envelope below 2^63 (see sparse_prior_fast.cpp).
inline constexpr int kMaxSparsePriorSide = 4096;

namespace detail {

// The one snapping rule every implementation uses (the shaders write floor(v + 0.5) too).
inline int snap(float v) {
  return static_cast<int>(std::floor(v + 0.5f));
}
inline int64_t empty_dist2(const SparsePriorShape& s) {
  return static_cast<int64_t>(s.width) * s.width + static_cast<int64_t>(s.height) * s.height;
}
inline float inv_two_sigma2(const SparsePriorShape& s) {
  return 1.f / (2.f * s.sigma_px * s.sigma_px);
}

// Throws unless out holds both planes.
void check_out(const SparsePriorShape& s, std::span<const float> out);

}  // namespace detail
}  // namespace pensight::kernels
