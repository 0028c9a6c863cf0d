#include "pipeline/fft/grid_plan.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pensight {
namespace {

constexpr double kReferenceRoi_px = 300, kReferenceFx_px = 462, kReferenceBar_m = 0.030;
constexpr int kMinPlannedRoi_px = 32, kMaxPlannedFft = 256;
// A planned ROI takes at most this share of the frame's smaller side (less the border), so the
// grid's rows (or columns) keep a baseline of 15 % of it: ROIs as tall as a 640x480 frame put
// every row's centre on one line, the points then fix no pitch, and an 80 px diamond gave no
// pose (0-2 of 5 frames); 400 px ROIs give 5 of 5 at 0.01 %.
constexpr double kMaxRoiShareOfSide = 0.85;
// Smaller frames hold too few cells for the planned grid at any distance worth a pose.
constexpr int kMinPlannedWidth_px = 160, kMinPlannedHeight_px = 120;

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
    const std::string frame =
        std::to_string(camera.width_px) + "x" + std::to_string(camera.height_px) + " frame";
    if (camera.width_px < kMinPlannedWidth_px || camera.height_px < kMinPlannedHeight_px) {
      const std::string least =
          std::to_string(kMinPlannedWidth_px) + "x" + std::to_string(kMinPlannedHeight_px);
      throw Error("net detector: a " + frame + " is below the " + least +
                  " the ROI grid is planned for; use frames of " + least +
                  " or more, or give the ROI side (--roi-size, grid.roi_size_px) for a smaller "
                  "one");
    }
    const int fit = std::min(camera.width_px, camera.height_px) - c.grid.border_px;
    if (fit < kernels::kMinRoiSize_px) {
      throw Error("net detector: a " + frame + " with a border of " +
                  std::to_string(c.grid.border_px) + " px leaves no room for a ROI of " +
                  std::to_string(kernels::kMinRoiSize_px) + " px; use a smaller border");
    }
    const double wanted =
        kReferenceRoi_px * (camera.fx_px / kReferenceFx_px) * (c.bar_length_m / kReferenceBar_m);
    const long rounded = std::isfinite(wanted) ? std::lround(wanted) : kMinPlannedRoi_px;
    const int most =
        std::max(std::min(kMinPlannedRoi_px, fit), static_cast<int>(kMaxRoiShareOfSide * fit));
    int roi = static_cast<int>(std::clamp<long>(rounded, std::min(kMinPlannedRoi_px, fit), most));
    // Below the FFT cap a power of two within 25 % of the side is taken as the side, so the FFT
    // reads the ROI's own pixels instead of resampling them (a 3 px mesh keeps its 3 px).
    if (roi < kMaxPlannedFft) {
      const int below = largest_power_of_two_at_most(roi), above = 2 * below;
      const int nearest = std::log2(static_cast<double>(roi) / below) < 0.5 ? below : above;
      const double ratio = static_cast<double>(nearest) / roi;
      if (ratio >= 0.8 && ratio <= 1.25 && nearest <= most && nearest >= kernels::kMinRoiSize_px) {
        roi = nearest;
      }
    }
    c.grid.roi_size_px = roi;
  }
  if (c.fft_size == 0) {
    c.fft_size =
        std::max(kernels::kMinFftSize,
                 largest_power_of_two_at_most(std::min(c.grid.roi_size_px, kMaxPlannedFft)));
  }
  return c;
}

}  // namespace pensight
