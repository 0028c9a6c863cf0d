#include "tests/support/depth_models.h"

#include <vector>

#include "kernels/nn/nn.h"
#include "kernels/nn/nn_onnx.h"

namespace pensight::testing {

namespace {

// depth = a 1x1 conv over (image, the prior's channels) with `weights`, one per channel: a model
// of the stage's contract whose output a test knows.
void write_channel_pick_model(const std::filesystem::path& file, int width, int height,
                              std::vector<float> weights) {
  const int channels = static_cast<int>(weights.size());
  kernels::Graph g;
  const int image = g.add_input("image", {1, 1, height, width});
  const int prior = g.add_input("prior", {1, channels - 1, height, width});
  kernels::Attrs cat;
  cat.axis = 1;
  const int x = g.add(kernels::Op::kConcat, {image, prior}, cat);
  const int pick = g.add_constant("pick", {{1, channels, 1, 1}, std::move(weights)});
  const int depth = g.add(kernels::Op::kConv, {x, pick});
  g.values()[static_cast<size_t>(depth)].name = "depth";
  g.mark_output(depth);
  kernels::export_onnx(g, file);
}

}  // namespace

void write_s1_depth_model(const std::filesystem::path& file, int width, int height, float gain) {
  write_channel_pick_model(file, width, height, {0.f, gain, 0.f});
}

void write_surface_depth_model(const std::filesystem::path& file, int width, int height) {
  write_channel_pick_model(file, width, height, {0.f, 0.f, 0.f, 1.f});
}

}  // namespace pensight::testing
