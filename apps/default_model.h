#pragma once
// Where the command line finds a shipped depth network when no --model is given.
#include <filesystem>

#include "core/camera.h"

namespace pensight::app {

inline constexpr const char* kModelsDir = "models";  // in the source tree

// Among the compact_depth*.onnx files of $PENSIGHT_MODEL_DIR, then of the source tree's models/
// seen from the executable (build/apps/pensight -> models/), in name order: the first whose
// input has the camera's aspect (compact_depth.onnx: 320x240 for 4:3; compact_depth_512x288.onnx
// for 16:9). Empty when none does.
std::filesystem::path find_default_depth_model(const PinholeCamera& camera);

}  // namespace pensight::app
