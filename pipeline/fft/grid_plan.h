#pragma once
// The ROI side and FFT size for a camera and a mesh, where NetDetectorConfig leaves them at 0, so
// a user need not know what an ROI is to get a pose from their camera.
//
// Rule: a ROI holds as many of the net's cells as the reference set-up's does (300 px ROIs on
// 720x540 at fx 462 px, 30 mm bars: 7.5-37 cells at 0.4-2.5 m). A cell's image scales with
// fx * bar / distance, so the side is 300 px * (fx / 462 px) * (bar / 30 mm): 300 px at the
// reference, 438 px on SOLAQUA's 1280x720 (fx 735, 27.5 mm), 800 px on a 1920x1080 camera of the
// reference's field of view. Within the frame: at most 85 % of its smaller side less the border
// (the grid keeps a baseline across that side), at least 32 px; below 256 px a power of two
// within 25 % is taken instead (133 -> 128 px on 320x240, 109 -> 128 on SOLAQUA at a quarter
// size). The FFT side is the largest power of two at
// most min(ROI, 256): from 256 px ROIs on the reference's bins per cell (and its FFT cost), below
// that the ROI's own pixels. Rows x cols stay the configuration's (the pose's ROI counts are set
// for 5 x 6).
// Cost: a few operations, once per camera.
#include "core/camera.h"
#include "pipeline/fft/net_detector.h"

namespace pensight {

// `config` with grid.roi_size_px and fft_size planned where they are 0; values given stay.
// Throws pensight::Error, when it plans, for a frame below 160x120 (a smaller one needs the ROI
// side given) and for a border that leaves under 16 px for a ROI.
// Validation of the result (the grid fits the frame, fft_size <= ROI) is NetDetector's.
NetDetectorConfig planned_detector_config(const NetDetectorConfig& config,
                                          const PinholeCamera& camera);

}  // namespace pensight
