#pragma once
// A ROI's range error against the rendered net's truth, as the kernel's lattice measures it and as
// the chirp correction (pipeline/fft/lattice_chirp.h) corrects it on the true plane.
#include <cmath>
#include <numbers>
#include <utility>

#include "pipeline/fft/lattice_chirp.h"
#include "pipeline/fft/net_detector.h"
#include "tests/support/net_image.h"

namespace pensight::testing {

// ROI i's range / truth - 1 from a detection made with the correction off: as measured, and
// corrected on the scene's true plane (1 where the corrected ROI is not valid). Square mesh.
inline std::pair<double, double> roi_range_errors(const NetDetection& d, size_t i,
                                                  const NetDetector& detector,
                                                  const PinholeCamera& cam, const NetScene& s) {
  const Eigen::Vector3d normal = net_plane_normal(std::tan(s.psi_rad), std::tan(s.pitch_rad));
  const Eigen::Vector2d px = d.points[i].centre_px;
  const double truth = ray_on_plane(cam.ray(px), {0, 0, s.distance_m}, normal).norm();
  const kernels::RoiOrigin o = detector.rois()[i];
  const MeshModel mesh{s.bar_length_m, std::numbers::pi / 2};
  const RoiNetPoint corrected = roi_net_point(
      chirp_corrected(d.lattices[i], o, 300, px, cam, normal), o, 300, cam, mesh, {}, &normal);
  return {d.points[i].range_m / truth - 1, corrected.valid() ? corrected.range_m / truth - 1 : 1.0};
}

}  // namespace pensight::testing
