#include "sim/lamp_veil_table.h"

#include <algorithm>
#include <cmath>

#include "sim/lamp_veil.h"

namespace pensight::sim {
namespace {

// Grid point k sits on pixel coordinate k * kStep_px - 0.5, so the grid covers the image's edges.
double grid_px(int k) {
  return k * LampVeilTable::kStep_px - 0.5;
}

}  // namespace

LampVeilTable::LampVeilTable(const PinholeCamera& camera, const std::vector<LampPose>& lamps_camera,
                             double attenuation_per_m, double strength, double range_m)
    : cells_x_((camera.width_px + kStep_px - 1) / kStep_px),
      cells_y_((camera.height_px + kStep_px - 1) / kStep_px),
      w_max_(std::log1p(range_m / kLampVeilScale_m)) {
  const int points_x = cells_x_ + 1, points_y = cells_y_ + 1;
  std::vector<float> value(static_cast<size_t>(points_x) * points_y * kNodes);
  for (int gy = 0; gy < points_y; ++gy) {
    for (int gx = 0; gx < points_x; ++gx) {
      const Eigen::Vector3d d = camera.ray({grid_px(gx), grid_px(gy)}).normalized();
      for (int j = 0; j < kNodes; ++j) {
        const double t = kLampVeilScale_m * std::expm1(w_max_ * j / (kNodes - 1));
        value[(static_cast<size_t>(gy) * points_x + gx) * kNodes + j] = static_cast<float>(
            strength * lamp_veil(Eigen::Vector3d::Zero(), d, t, lamps_camera, attenuation_per_m));
      }
    }
  }
  cells_.resize(static_cast<size_t>(cells_x_) * cells_y_ * kNodes);
  for (int cy = 0; cy < cells_y_; ++cy) {
    for (int cx = 0; cx < cells_x_; ++cx) {
      for (int j = 0; j < kNodes; ++j) {
        auto v = [&](int gx, int gy) {
          return value[(static_cast<size_t>(gy) * points_x + gx) * kNodes + j];
        };
        cells_[(static_cast<size_t>(cy) * cells_x_ + cx) * kNodes + j] = {
            v(cx, cy), v(cx + 1, cy), v(cx, cy + 1), v(cx + 1, cy + 1)};
      }
    }
  }
}

double LampVeilTable::at(double x_px, double y_px, double t_m) const {
  const double u =
      std::log1p(std::clamp(t_m, 0.0, kLampVeilScale_m * std::expm1(w_max_)) / kLampVeilScale_m) /
      w_max_ * (kNodes - 1);
  const int j = std::min(static_cast<int>(u), kNodes - 2);
  const double fu = u - j;
  const double gx = std::max((x_px + 0.5) / kStep_px, 0.0),
               gy = std::max((y_px + 0.5) / kStep_px, 0.0);
  const int cx = std::min(static_cast<int>(gx), cells_x_ - 1);
  const int cy = std::min(static_cast<int>(gy), cells_y_ - 1);
  const double fx = gx - cx, fy = gy - cy;
  const size_t c = (static_cast<size_t>(cy) * cells_x_ + cx) * kNodes + j;
  std::array<double, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = cells_[c][k] + fu * (cells_[c + 1][k] - cells_[c][k]);
  const double top = v[0] + fx * (v[1] - v[0]), bottom = v[2] + fx * (v[3] - v[2]);
  return top + fy * (bottom - top);
}

}  // namespace pensight::sim
