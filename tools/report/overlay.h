#pragma once
// A camera frame with what the FFT net detection saw on it, like the published Fig. 2a: each
// ROI's square coloured by its part in the pose, a few cells of each ROI's detected lattice, and
// the frame's d_net / psi_net / pitch_net (or why the pose is NaN). docs/report.md shows one.
#include <filesystem>
#include <span>

#include "core/image.h"
#include "kernels/fft_roi/fft_roi.h"
#include "pipeline/fft/net_detector.h"

namespace pensight {

// Writes `file` whole as a colour PNG of the frame's size, with the grid the detection was made
// on (NetDetection::rois, roi_size_px). Throws pensight::Error when the frame is empty, the
// detection's points and ROIs differ in number, or the file cannot be written.
void write_overlay_png(const std::filesystem::path& file, const ImageU8& frame,
                       const NetDetection& detection);

}  // namespace pensight
