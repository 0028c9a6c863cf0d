#pragma once
// Where the command line finds a shipped depth network when no --model is given.
#include <filesystem>

#include "core/camera.h"

namespace pensight::app {

inline constexpr const char* kModelsDir = "models";  // in the source tree

// Among the compact_depth*.onnx files of $PENSIGHT_MODEL_DIR, else of the source tree's models/
// seen from the executable (build/apps/pensight -> models/), in name order: the first whose
// input sees the most of the camera's frame (network_view: compact_depth.onnx, 320x240, all of a
// 4:3 frame; compact_depth_512x288.onnx all of a 16:9 one; any other aspect its centred crop).
// Empty when the folders hold no model this build reads.
std::filesystem::path find_default_depth_model(const PinholeCamera& camera);

}  // namespace pensight::app
