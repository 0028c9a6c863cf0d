#pragma once
// Marine snow: particles fixed in the water, which drifts with the scenario's current, so they
// move consistently from frame to frame (drift plus parallax of the camera's own motion). Both
// renderers draw the same spots: the CPU reference splats them, the Vulkan renderer bins them
// into tiles (sim/render_vk.cpp).
#include <vector>

#include "sim/frame_state.h"

namespace pensight::sim {

// A particle seen by the camera: a Gaussian spot of radiance `peak` at its centre, lit by the
// ambient light and the lamps (so the nearest particles glow) and attenuated by the water
// between it and the camera.
struct SnowSpot {
  double x_px = 0, y_px = 0, sigma_px = 1, peak = 0;
};

// Spots add nothing beyond this many sigmas (exp(-8) = 3e-4 of the peak); both renderers cut
// there, so they agree pixel for pixel.
inline constexpr double kSnowCutoffSigmas = 4;
// Particles are drawn between these distances from the camera: nearer ones would be blurred
// blobs filling the lens, farther ones are sub-pixel, dimly lit and faded.
inline constexpr double kSnowNear_m = 0.15, kSnowFar_m = 2.0;

// The spots of frame f (empty when the scenario has no marine snow). The particle field is a
// function of the seed alone, cells of water moving with current_mps * f.t_s.
std::vector<SnowSpot> snow_spots(const Scenario& s, const FrameState& f);

// Radiance added by `spot` at pixel (x, y), 0 beyond kSnowCutoffSigmas.
double snow_radiance(const SnowSpot& spot, double x, double y);

}  // namespace pensight::sim
