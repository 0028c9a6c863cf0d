#pragma once
// The FFT net detector's parameters, each defined once (core/params.h): a table per part of
// NetDetectorConfig, keyed by member name under the part's member name ("peaks.min_cycles"; the
// config's own scalars without a prefix). The config is built in code (Pipeline, `pensight run`,
// the ROS node), so the tables check it (validate) and document it (`pensight params`); no YAML
// file reads them.
#include <string>

#include "pipeline/fft/net_detector.h"

namespace pensight {

// Throws pensight::Error "net detector config: key 'PREFIX.KEY': VALUE is outside RANGE UNIT
// (HELP)" for the first parameter out of its range, then checks the rules that tie parameters
// together: fft_size at most grid.roi_size_px and a power of two unless the backend is the CPU's
// (the shaders and cuFFT plans are radix-2; kAuto may choose them), and a non-empty peak band
// (peaks.min_cycles below peaks.max_nyquist_share * fft_size / 2). Whether the grid fits the
// image is the camera's to say (kernels::roi_grid).
void validate(const NetDetectorConfig& config);

// Markdown rows (under core/params.h's kParamTableHeader) of every parameter, defaults those of
// NetDetectorConfig{}.
std::string net_detector_param_rows();

}  // namespace pensight
