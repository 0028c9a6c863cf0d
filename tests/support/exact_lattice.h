#pragma once
// Exact per-ROI lattices for tests of the net geometry: the RoiLattice a spectrum analysis would
// report for given image lattice vectors.
#include <Eigen/Core>
#include <Eigen/LU>

#include "kernels/fft_roi/fft_roi.h"

namespace pensight::testing {

// Frequencies dual to the columns of a_px (image lattice vectors, pixels), with a quality and a
// contrast that pass every ROI check.
inline kernels::RoiLattice lattice_of(const Eigen::Matrix2d& a_px) {
  const Eigen::Matrix2d f = a_px.inverse().transpose();
  return {static_cast<float>(f(0, 0)),
          static_cast<float>(f(1, 0)),
          static_cast<float>(f(0, 1)),
          static_cast<float>(f(1, 1)),
          0.3f,
          50.0f};
}

}  // namespace pensight::testing
