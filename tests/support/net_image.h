#pragma once
// Analytic test frames for the FFT net detector until the renderer lands: a planar square net in
// front of the camera, ray-traced through pensight::PinholeCamera (distortion included) with
// the twine pattern filtered analytically by the pixel footprint and the lens PSF before
// sampling (so thin, far twine is band-limited like in a real camera instead of aliasing), and
// frames without a net.
#include <cstdint>

#include "pipeline/camera.h"
#include "runtime/image.h"

namespace pensight::testing {

struct NetScene {
  double distance_m = 1.0;  // along the optical axis to the net plane (= d_net)
  double psi_rad = 0;       // net plane z = tan(psi) x + tan(pitch) y + d in C (dataset signs)
  double pitch_rad = 0;
  double mesh_m = 0.030;                     // twine centre-to-centre spacing
  double twine_m = 0.003;                    // twine width
  double twine_rotation_rad = 0;             // twine directions within the net plane
  double net_level = 190, water_level = 70;  // grey levels
  double attenuation_m = 0;                  // > 0: contrast falls as exp(-range / attenuation_m)
  double blur_sigma_px = 0.6;  // Gaussian PSF of lens and sensor (no real camera has none)
  double noise_sigma = 2;      // Gaussian pixel noise, grey levels
  double edge_m = 1e9;         // the net ends this far right of the optical axis, in the net plane
  uint64_t seed = 1;
};

ImageU8 render_net(const PinholeCamera& camera, const NetScene& scene);
// Uniform random grey levels in [lo, hi].
ImageU8 render_noise(int width, int height, int lo, int hi, uint64_t seed);

}  // namespace pensight::testing
