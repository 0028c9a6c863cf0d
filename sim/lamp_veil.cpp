#include "sim/lamp_veil.h"

#include <algorithm>
#include <cmath>

namespace pensight::sim {

double lamp_veil(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double t_end,
                 const std::vector<LampPose>& lamps, double attenuation_per_m, int samples) {
  if (!(t_end > 0) || lamps.empty()) return 0;
  // s = s0 (e^w - 1), ds = (s + s0) dw: the steps grow with the distance, as the beams widen
  // and the light falls off.
  const double s0 = kLampVeilScale_m, dw = std::log1p(t_end / s0) / samples;
  // e^w of the midpoints by repeated multiplication, one exp for the whole ray.
  const double ratio = std::exp(dw);
  double growth = std::exp(0.5 * dw), sum = 0;
  for (int i = 0; i < samples; ++i, growth *= ratio) {
    const double s = s0 * (growth - 1);
    const Eigen::Vector3d p = origin + s * d;
    for (const LampPose& l : lamps) {
      const Eigen::Vector3d v = p - l.position_m;
      const double r2 = v.squaredNorm(), r = std::sqrt(r2);
      const double ca = v.dot(l.direction) / r;
      if (ca <= 0) continue;
      // cos^m fall-off and the attenuation both ways in one exp; ds = (s + s0) dw.
      sum += l.intensity * (s + s0) *
             std::exp(l.exponent * std::log(ca) - attenuation_per_m * (r + s)) / std::max(r2, 0.01);
    }
  }
  return sum * dw;
}

}  // namespace pensight::sim
