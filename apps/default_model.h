#pragma once
// Where the command line finds the shipped depth network when no --model is given.
#include <filesystem>

namespace pensight::app {

inline constexpr const char* kDefaultDepthModel = "models/compact_depth.onnx";

// The first that exists of: $PENSIGHT_MODEL_DIR/compact_depth.onnx, the source tree's models/
// seen from the executable (build/apps/pensight -> models/), <prefix>/share/pensight/models/.
// Empty when none does.
std::filesystem::path find_default_depth_model();

}  // namespace pensight::app
