#pragma once
// Depth networks of the stage's contract for tests, written as ONNX files.
#include <filesystem>

namespace pensight::testing {

// depth = gain x S1 (a 1x1 conv over image, S1, S2 with weights 0, gain, 0): the nearest prior's
// depth at every pixel, scaled, so a test knows what the stage must output. width x height: the
// network's input.
void write_s1_depth_model(const std::filesystem::path& file, int width, int height, float gain = 1);

// depth = Q, the third prior channel (pipeline/depth/prior_surface.h): a model with the
// three-channel prior input that returns the surface the stage fed it.
void write_surface_depth_model(const std::filesystem::path& file, int width, int height);

}  // namespace pensight::testing
