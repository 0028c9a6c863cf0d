#include <string>

#include "core/error.h"
#include "kernels/fft_roi/fft_roi.h"

namespace pensight::kernels {

std::vector<RoiOrigin> roi_grid(int width, int height, const RoiGrid& g) {
  if (g.rows < 1 || g.cols < 1) {
    throw Error("roi_grid: rows and cols must be >= 1, got " + std::to_string(g.rows) + " x " +
                std::to_string(g.cols));
  }
  if (g.roi_size_px < kMinRoiSize_px || g.border_px < 0 || g.border_px + g.roi_size_px > width ||
      g.border_px + g.roi_size_px > height) {
    throw Error("roi_grid: ROIs of " + std::to_string(g.roi_size_px) + " px with a border of " +
                std::to_string(g.border_px) + " px do not fit a " + std::to_string(width) + "x" +
                std::to_string(height) + " image; use a smaller --roi-size or --roi-border");
  }
  // Corners are spread evenly over [border, far edge - size]; integer positions, rounded.
  auto spread = [&](int i, int count, int extent) {
    if (count == 1) return g.border_px;
    const int span = extent - g.roi_size_px - g.border_px;
    return g.border_px + (2 * i * span + (count - 1)) / (2 * (count - 1));
  };
  std::vector<RoiOrigin> rois;
  rois.reserve(static_cast<size_t>(g.rows) * g.cols);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c)
      rois.push_back({spread(c, g.cols, width), spread(r, g.rows, height)});
  }
  return rois;
}

void validate(const FftRoiShape& s, FftSizes sizes) {
  if (s.width <= 0 || s.height <= 0 || s.roi_size_px < kMinRoiSize_px || s.roi_size_px > s.width ||
      s.roi_size_px > s.height) {
    throw Error("fft_roi: ROI size " + std::to_string(s.roi_size_px) + " does not fit a " +
                std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
  }
  const bool pow2 = (s.fft_size & (s.fft_size - 1)) == 0;
  if (s.fft_size < kMinFftSize || s.fft_size > s.roi_size_px || s.fft_size > 1024 ||
      (sizes == FftSizes::kPowerOfTwo && !pow2)) {
    throw Error("fft_roi: FFT size " + std::to_string(s.fft_size) + " is unusable for ROIs of " +
                std::to_string(s.roi_size_px) + " px; use " +
                (sizes == FftSizes::kPowerOfTwo ? "a power of two " : "a size ") +
                "between 16 and min(roi size, 1024), e.g. 256 or 128");
  }
}

void validate(const FftRoiShape& s, std::span<const RoiOrigin> rois) {
  for (size_t i = 0; i < rois.size(); ++i) {
    const RoiOrigin& r = rois[i];
    if (r.x < 0 || r.y < 0 || r.x + s.roi_size_px > s.width || r.y + s.roi_size_px > s.height) {
      throw Error("fft_roi: ROI " + std::to_string(i) + " at (" + std::to_string(r.x) + ", " +
                  std::to_string(r.y) + ") of size " + std::to_string(s.roi_size_px) +
                  " leaves the " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                  " image");
    }
  }
}

}  // namespace pensight::kernels
