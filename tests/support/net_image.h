#pragma once
// Analytic test frames for the FFT net detector: a planar net of rhombic cells (square or
// diamond mesh at any opening angle, optional knots) in front of the camera, ray-traced through
// pensight::PinholeCamera (distortion included) with the twine pattern filtered analytically by the
// pixel footprint and the lens PSF before sampling (so thin, far twine is band-limited like in a
// real camera instead of aliasing), and frames without a net.
#include <cstdint>

#include <numbers>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "core/image.h"

namespace pensight::testing {

struct NetScene {
  double distance_m = 1.0;  // along the optical axis to the net plane (= d_net)
  double psi_rad = 0;       // net plane z = tan(psi) x + tan(pitch) y + d in C (dataset signs)
  double pitch_rad = 0;
  double bar_length_m = 0.030;  // bar length, knot to knot
  double twine_m = 0.003;       // twine width, across the twine
  double knot_m = 0;            // side of the knots at the crossings (0: knotless)
  // Square: one bar along the net's right, the other at the opening angle from it towards the
  // net's up (-y_C projected onto the net). Diamond: bars at +-angle/2 from the net's up.
  MeshType mesh_type = MeshType::kSquare;
  double opening_angle_rad = std::numbers::pi / 2;
  double twine_rotation_rad = 0;             // the whole lattice, within the net plane
  double net_level = 190, water_level = 70;  // grey levels
  double attenuation_m = 0;                  // > 0: contrast falls as exp(-range / attenuation_m)
  double blur_sigma_px = 0.6;  // Gaussian PSF of lens and sensor (no real camera has none)
  double noise_sigma = 2;      // Gaussian pixel noise, grey levels
  double edge_m = 1e9;         // the net ends this far right of the optical axis, in the net plane
  // The lattice moved within the net plane along the net's right and up (the unrotated ones), as
  // when the camera moves the other way along the net.
  double shift_right_m = 0, shift_up_m = 0;
  uint64_t seed = 1;
};

ImageU8 render_net(const PinholeCamera& camera, const NetScene& scene);
// Uniform random grey levels in [lo, hi].
ImageU8 render_noise(int width, int height, int lo, int hi, uint64_t seed);

}  // namespace pensight::testing
