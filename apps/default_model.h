#pragma once
// Where the command line finds the shipped depth network when no --model is given.
#include <filesystem>

namespace pensight::app {

inline constexpr const char* kDefaultDepthModel = "models/compact_depth.onnx";

// The first that exists of: $PENSIGHT_MODEL_DIR/compact_depth.onnx and the source tree's models/
// seen from the executable (build/apps/pensight -> models/). Empty when neither does.
std::filesystem::path find_default_depth_model();

}  // namespace pensight::app
