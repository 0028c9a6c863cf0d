#include "pipeline/fft/grid_plan.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pensight {
namespace {

constexpr double kReferenceRoi_px = 300, kReferenceFx_px = 462, kReferenceBar_m = 0.030;
constexpr int kMinPlannedRoi_px = 32, kMaxPlannedFft = 256;

int largest_power_of_two_at_most(int n) {
  int p = 1;
  while (2 * p <= n) p *= 2;
  return p;
}

}  // namespace

NetDetectorConfig planned_detector_config(const NetDetectorConfig& config,
                                          const PinholeCamera& camera) {
  NetDetectorConfig c = config;
  if (c.grid.roi_size_px == 0) {
    const int fit = std::min(camera.width_px, camera.height_px) - c.grid.border_px;
    if (fit < kernels::kMinRoiSize_px) {
      throw Error("net detector: a " + std::to_string(camera.width_px) + "x" +
                  std::to_string(camera.height_px) + " frame with a border of " +
                  std::to_string(c.grid.border_px) + " px leaves no room for a ROI of " +
                  std::to_string(kernels::kMinRoiSize_px) +
                  " px; frames from 160x120 up work (a smaller border, or a larger frame)");
    }
    const double wanted =
        kReferenceRoi_px * (camera.fx_px / kReferenceFx_px) * (c.bar_length_m / kReferenceBar_m);
    const long rounded = std::isfinite(wanted) ? std::lround(wanted) : kMinPlannedRoi_px;
    c.grid.roi_size_px =
        static_cast<int>(std::clamp<long>(rounded, std::min(kMinPlannedRoi_px, fit), fit));
  }
  if (c.fft_size == 0) {
    c.fft_size =
        std::max(kernels::kMinFftSize,
                 largest_power_of_two_at_most(std::min(c.grid.roi_size_px, kMaxPlannedFft)));
  }
  return c;
}

}  // namespace pensight
