#include "vehicle/ocean_current.h"

#include <cmath>

namespace pensight::vehicle {

OceanCurrent::OceanCurrent(const CurrentParams& params) : params_(params), rng_(params.seed) {
  if (params_.variation_mps == 0) return;  // normal_distribution needs a positive sigma
  std::normal_distribution<double> normal(0.0, params_.variation_mps);
  variation_pen_mps_.head<2>() << normal(rng_), normal(rng_);
}

void OceanCurrent::advance(double dt_s) {
  if (params_.variation_mps == 0 || dt_s <= 0) return;
  const double a = std::exp(-dt_s / params_.time_constant_s);
  std::normal_distribution<double> normal(0.0, params_.variation_mps * std::sqrt(1 - a * a));
  variation_pen_mps_.head<2>() = a * variation_pen_mps_.head<2>();
  variation_pen_mps_.x() += normal(rng_);
  variation_pen_mps_.y() += normal(rng_);
}

}  // namespace pensight::vehicle
