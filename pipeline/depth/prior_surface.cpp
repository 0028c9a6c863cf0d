#include "pipeline/depth/prior_surface.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pensight {

namespace {

constexpr std::array<double, 6> kRidge = {0, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3};

Eigen::Matrix<double, 6, 1> basis(double u, double v) {
  Eigen::Matrix<double, 6, 1> a;
  a << 1, u, v, u * u, u * v, v * v;
  return a;
}

using Coefficients = Eigen::Matrix<double, 6, 1>;

// The curvatures of `wall` seen along the normal that the plane part of `c` implies (header);
// 0 where the wall's curvature or focal length is not given or the plane is not a wall.
Coefficients wall_curvatures(const Coefficients& c, double m_ref_m, double half_width_px,
                             const NetWallShape& wall) {
  Coefficients target = Coefficients::Zero();
  if (!(wall.curvature_per_m > 0) || !(wall.focal_px > 0)) return target;
  const double s = half_width_px / wall.focal_px;
  const Eigen::Vector3d n = Eigen::Vector3d(c[1] / s, c[2] / s, c[0]).normalized();
  if (!(n.z() > 0) || std::abs(n.y()) > std::sqrt(0.5)) return target;
  target[3] =
      m_ref_m * wall.curvature_per_m * s * s / (2 * n.z() * (n.y() * n.y() + n.z() * n.z()));
  return target;
}

}  // namespace

PriorSurface fit_prior_surface(std::span<const SparseDepth> depths, int width, int height,
                               const NetWallShape& wall) {
  if (depths.empty() || width < 1 || height < 1) {
    throw Error("prior surface: needs at least one sparse depth and a positive image size");
  }
  auto usable = [](double q) { return q > 0 && std::isfinite(q); };
  const bool weighted = std::any_of(depths.begin(), depths.end(),
                                    [&](const SparseDepth& d) { return usable(d.quality); });
  auto weight = [&](const SparseDepth& d) {
    if (!weighted) return 1.0;
    return usable(d.quality) ? static_cast<double>(d.quality) : 0.0;
  };
  double sum_w = 0, sum_wz = 0;
  for (const SparseDepth& d : depths) {
    const double z = d.point.depth_m;
    if (!(z > 0) || !std::isfinite(z)) {
      throw Error("prior surface: sparse depth " + std::to_string(z) + " m at (" +
                  std::to_string(d.point.x_px) + ", " + std::to_string(d.point.y_px) +
                  ") is not positive and finite");
    }
    const double w = weight(d);
    sum_w += w;
    sum_wz += w * z;
  }
  PriorSurface s;
  s.width = width;
  s.height = height;
  s.m_ref_m = sum_wz / sum_w;
  s.t_min = s.t_max = s.m_ref_m / depths.front().point.depth_m;
  const double half = width / 2.0, cx = (width - 1) / 2.0, cy = (height - 1) / 2.0;
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Coefficients rhs = Coefficients::Zero();
  for (const SparseDepth& d : depths) {
    const double t = s.m_ref_m / d.point.depth_m;
    s.t_min = std::min(s.t_min, t);
    s.t_max = std::max(s.t_max, t);
    const double w = weight(d);
    const auto a = basis((d.point.x_px - cx) / half, (d.point.y_px - cy) / half);
    normal.noalias() += w * a * a.transpose();
    rhs.noalias() += w * t * a;
  }
  Coefficients ridge;
  for (int i = 0; i < 6; ++i) ridge[i] = kRidge[i] * sum_w;
  normal.diagonal() += ridge;
  const auto solver = normal.ldlt();
  Coefficients c = solver.solve(rhs);
  const Coefficients target = wall_curvatures(c, s.m_ref_m, half, wall);
  if (!target.isZero()) c = solver.solve(rhs + ridge.cwiseProduct(target));
  std::copy(c.data(), c.data() + 6, s.c.begin());
  return s;
}

void render_prior_surface(const PriorSurface& s, std::span<float> out) {
  const size_t n = static_cast<size_t>(s.width) * s.height;
  if (out.size() < n) {
    throw Error("prior surface: output holds " + std::to_string(out.size()) + " values, " +
                std::to_string(s.width) + "x" + std::to_string(s.height) + " needs " +
                std::to_string(n));
  }
  const double half = s.width / 2.0, cx = (s.width - 1) / 2.0, cy = (s.height - 1) / 2.0;
  const double lo = s.t_min / 2, hi = 2 * s.t_max;
  const auto& c = s.c;
  for (int y = 0; y < s.height; ++y) {
    const double v = (y - cy) / half;
    const double row0 = c[0] + c[2] * v + c[5] * v * v, row1 = c[1] + c[4] * v;
    float* o = out.data() + static_cast<size_t>(y) * s.width;
    for (int x = 0; x < s.width; ++x) {
      const double u = (x - cx) / half;
      const double t = row0 + u * (row1 + c[3] * u);
      o[x] = static_cast<float>(s.m_ref_m / std::clamp(t, lo, hi));
    }
  }
}

void align_to_priors(std::vector<float>& depth_m, int width, int height,
                     std::span<const SparseDepth> depths) {
  std::vector<SparseDepth> ratios;
  ratios.reserve(depths.size());
  for (const SparseDepth& d : depths) {
    const int x = static_cast<int>(std::floor(d.point.x_px + 0.5f));
    const int y = static_cast<int>(std::floor(d.point.y_px + 0.5f));
    if (x < 0 || y < 0 || x >= width || y >= height) continue;
    const float z = depth_m[static_cast<size_t>(y) * width + x];
    if (z > 0 && std::isfinite(z) && d.point.depth_m > 0 && std::isfinite(d.point.depth_m)) {
      ratios.push_back({{d.point.x_px, d.point.y_px, d.point.depth_m / z}, d.quality});
    }
  }
  if (ratios.empty()) return;
  std::vector<float> factor(depth_m.size());
  render_prior_surface(fit_prior_surface(ratios, width, height), factor);
  for (size_t i = 0; i < depth_m.size(); ++i) depth_m[i] *= factor[i];
}

}  // namespace pensight
