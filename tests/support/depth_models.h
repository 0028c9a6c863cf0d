#pragma once
// Depth networks of the stage's contract for tests, written as ONNX files.
#include <filesystem>

namespace pensight::testing {

// depth = S1 (a 1x1 conv over image, S1, S2 with weights 0, 1, 0): the nearest prior's depth at
// every pixel, so a test knows what the stage must output. width x height: the network's input.
void write_s1_depth_model(const std::filesystem::path& file, int width, int height);

}  // namespace pensight::testing
