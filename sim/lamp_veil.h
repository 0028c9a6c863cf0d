#pragma once
// The lamps' backscatter: light of each lamp's beam scattered once towards the camera along a
// camera ray, so the veil is bright where the ray crosses a beam near its lamp and fades outside
// the cone. The CPU reference uses this; shaders/sim/render.comp has the same quadrature.
#include <Eigen/Core>
#include <vector>

#include "sim/frame_state.h"

namespace pensight::sim {

// Quadrature points along the ray (midpoints in ln(1 + s / kLampVeilScale_m), dense near the
// camera where the beams start).
inline constexpr int kLampVeilSamples = 12;
inline constexpr double kLampVeilScale_m = 0.1;

// Integral over s in [0, t_end] of sum_lamps I cos(a)^m / r^2 exp(-c (r + s)) (lit only inside
// the beam, cos(a) > 0; r >= 0.1 m as in the lamps' irradiance), the radiance scattered towards
// the camera per unit scattering strength (times water.lamp_backscatter). `d` is a unit ray
// from `origin`; t_end must be finite (cut at the visible range by the caller).
double lamp_veil(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double t_end,
                 const std::vector<LampPose>& lamps, double attenuation_per_m,
                 int samples = kLampVeilSamples);

}  // namespace pensight::sim
