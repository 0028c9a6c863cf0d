#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "kernels/sparse_prior/sparse_prior.h"
#include "kernels/sparse_prior/sparse_prior_detail.h"

namespace pensight::kernels {

void validate(const SparsePriorShape& s, std::span<const SparsePoint> points) {
  if (s.width <= 0 || s.height <= 0 || s.width > kMaxSparsePriorSide ||
      s.height > kMaxSparsePriorSide) {
    throw Error("sparse_prior: image size " + std::to_string(s.width) + "x" +
                std::to_string(s.height) + " is outside 1.." + std::to_string(kMaxSparsePriorSide));
  }
  if (!(s.sigma_px > 0) || !std::isfinite(s.sigma_px)) {
    throw Error("sparse_prior: sigma_px must be positive and finite, got " +
                std::to_string(s.sigma_px));
  }
  if (points.size() > static_cast<size_t>(kMaxSparsePoints)) {
    throw Error("sparse_prior: " + std::to_string(points.size()) + " points, at most " +
                std::to_string(kMaxSparsePoints) + " are supported; subsample them first");
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const SparsePoint& p = points[i];
    const bool finite = std::isfinite(p.x_px) && std::isfinite(p.y_px) && std::isfinite(p.depth_m);
    const int x = finite ? detail::snap(p.x_px) : -1, y = finite ? detail::snap(p.y_px) : -1;
    if (!finite || x < 0 || y < 0 || x >= s.width || y >= s.height) {
      throw Error("sparse_prior: point " + std::to_string(i) + " (" + std::to_string(p.x_px) +
                  ", " + std::to_string(p.y_px) + ", depth " + std::to_string(p.depth_m) +
                  ") is not finite or lies outside the " + std::to_string(s.width) + "x" +
                  std::to_string(s.height) + " image; drop it before building the prior");
    }
  }
}

void detail::check_out(const SparsePriorShape& s, std::span<const float> out) {
  const size_t need = 2 * static_cast<size_t>(s.width) * s.height;
  if (out.size() < need) {
    throw Error("sparse_prior: output holds " + std::to_string(out.size()) + " floats, " +
                std::to_string(need) + " needed (2 planes of " + std::to_string(s.width) + "x" +
                std::to_string(s.height) + ")");
  }
}

NearestMap nearest_brute_force(const SparsePriorShape& s, std::span<const SparsePoint> points) {
  validate(s, points);
  const size_t n = static_cast<size_t>(s.width) * s.height;
  NearestMap m{std::vector<int32_t>(n, -1), std::vector<int64_t>(n, detail::empty_dist2(s))};
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const size_t i = static_cast<size_t>(y) * s.width + x;
      int64_t best = std::numeric_limits<int64_t>::max();
      for (size_t k = 0; k < points.size(); ++k) {
        const int64_t dx = x - detail::snap(points[k].x_px), dy = y - detail::snap(points[k].y_px);
        const int64_t d2 = dx * dx + dy * dy;
        if (d2 < best) {  // strict: the lowest index wins a tie
          best = d2;
          m.label[i] = static_cast<int32_t>(k);
          m.dist2_px2[i] = d2;
        }
      }
    }
  }
  return m;
}

void sparse_prior_from_nearest(const SparsePriorShape& s, std::span<const SparsePoint> points,
                               const NearestMap& nearest, std::span<float> out) {
  detail::check_out(s, out);
  const size_t n = static_cast<size_t>(s.width) * s.height;
  const float inv = detail::inv_two_sigma2(s);
  for (size_t i = 0; i < n; ++i) {
    const int32_t l = nearest.label[i];
    out[i] = l < 0 ? 0.f : points[static_cast<size_t>(l)].depth_m;
    out[n + i] = std::exp(-static_cast<float>(nearest.dist2_px2[i]) * inv);
  }
}

void sparse_prior_cpu_reference(const SparsePriorShape& s, std::span<const SparsePoint> points,
                                std::span<float> out) {
  detail::check_out(s, out);
  sparse_prior_from_nearest(s, points, nearest_brute_force(s, points), out);
}

}  // namespace pensight::kernels
