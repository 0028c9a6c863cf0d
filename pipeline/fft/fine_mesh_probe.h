#pragma once
// Whether a frame's mesh is finer than the grid's resampled ROIs hold. Where a ROI of R px is
// resampled to an FFT of F < R:
// - a lattice finer than the band (max_nyquist_share x F / 2 cycles per ROI) folds back into it
//   as a coarser one and reads as a nearer net: a 3 px mesh on 533 px ROIs at FFT 256 (a 30 mm
//   net 8 m from a 1280x720 camera) read 3.6 m on every frame;
// - a lattice of more than kMaxResampledCycles periods across the ROI leaves the band's low end
//   to whatever else the view holds at 4-10 cycles (fouling patches, caustics, a fish), which
//   resampling does not weaken as it weakens the lattice: a fouled 44 mm net 3.3 m from a 720x540
//   camera, 71 periods across 443 px ROIs, read 0.21 m from clean patches ~97 px apart.
// One ROI of F px at the frame's centre, analysed at its own pixels, sees such a lattice at its
// true period; NetDetector then analyses the frame on ROIs of F px (not resampled) instead.
//
// Cost: one F x F FFT on the CPU per frame (~0.2 ms at 256), and only for resampled grids.
#include <optional>
#include <string>

#include "core/image.h"
#include "kernels/fft_roi/fft_roi.h"

namespace pensight {

// The most lattice periods a resampled ROI is read with: the reference set-up's far end (a 30 mm
// mesh 2.5 m from the 720x540 camera, fx 462 px, on 300 px ROIs) holds 54. A planned ROI
// (grid_plan.h) holds 300 px / (462 px x 30 mm / d) = 21.6 periods per metre of distance d on any
// camera and mesh, so a net beyond ~2.6 m is read on native ROIs.
inline constexpr double kMaxResampledCycles = 56;
// After a frame read on native ROIs, the planned grid again only below this share of the limit:
// a net held near the limit's distance is not read on alternating grids.
inline constexpr double kReturnShare = 0.85;

class FineMeshProbe {
 public:
  // `grid`: the detector's shape; `min_quality`: a probe lattice weaker than this is no net.
  // Does nothing (too_fine() is always empty) when the grid does not resample.
  FineMeshProbe(const kernels::FftRoiShape& grid, const kernels::PeakParams& peaks,
                double min_quality);

  // The reason, naming the period and the fix, when the probe's lattice is finer than the grid
  // reads (kMaxResampledCycles, or kReturnShare of it after such a frame); empty otherwise, and
  // where the probe sees no lattice. `image` has the grid's size.
  std::optional<std::string> too_fine(const ImageU8& image);

 private:
  kernels::FftRoiShape grid_;
  double min_quality_ = 0;
  double max_cycles_ = 0;  // the most lattice periods across a ROI the grid reads
  bool native_ = false;    // the last frame with a probe lattice went to native ROIs
  kernels::RoiOrigin origin_;
  std::optional<kernels::FftRoiCpu> probe_;
};

}  // namespace pensight
