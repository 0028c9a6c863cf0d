#include "pipeline/fft/fine_mesh_probe.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pensight {

FineMeshProbe::FineMeshProbe(const kernels::FftRoiShape& grid, const kernels::PeakParams& peaks,
                             double min_quality)
    : grid_(grid), min_quality_(min_quality) {
  if (grid.roi_size_px <= grid.fft_size) return;
  const double band_max_cycles = double{peaks.max_nyquist_share} * grid.fft_size / 2;
  max_cycles_ = std::min(kMaxResampledCycles, band_max_cycles);
  kernels::FftRoiShape native = grid;
  native.roi_size_px = grid.fft_size;
  origin_ = {(grid.width - grid.fft_size) / 2, (grid.height - grid.fft_size) / 2};
  probe_.emplace(native, peaks, 1, kernels::FftPlanning::kQuick);
}

std::optional<std::string> FineMeshProbe::too_fine(const ImageU8& image) {
  if (!probe_) return std::nullopt;
  const kernels::RoiLattice l = probe_->run(image, {&origin_, 1}).front();
  if (!(l.quality >= min_quality_)) return std::nullopt;
  const double f_cpp = std::max(std::hypot(l.f1x, l.f1y), std::hypot(l.f2x, l.f2y));
  const double cycles = f_cpp * grid_.roi_size_px;
  const double limit = native_ ? kReturnShare * max_cycles_ : max_cycles_;
  native_ = cycles > limit;
  if (!native_) return std::nullopt;
  char reason[256];
  std::snprintf(reason, sizeof reason,
                "mesh period %.1f px: too fine for ROIs of %d px analysed at FFT %d (%.0f periods "
                "across, at most %.0f); analysed on ROIs of %d px",
                1 / f_cpp, grid_.roi_size_px, grid_.fft_size, cycles, limit, grid_.fft_size);
  return std::string(reason);
}

}  // namespace pensight
