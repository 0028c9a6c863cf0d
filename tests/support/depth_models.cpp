#include "tests/support/depth_models.h"

#include "kernels/nn/nn.h"
#include "kernels/nn/nn_onnx.h"

namespace pensight::testing {

void write_s1_depth_model(const std::filesystem::path& file, int width, int height, float gain) {
  nn::Graph g;
  const int image = g.add_input("image", {1, 1, height, width});
  const int prior = g.add_input("prior", {1, 2, height, width});
  nn::Attrs cat;
  cat.axis = 1;
  const int x = g.add(nn::Op::kConcat, {image, prior}, cat);
  const int weights = g.add_constant("pick_s1", {{1, 3, 1, 1}, {0.f, gain, 0.f}});
  const int depth = g.add(nn::Op::kConv, {x, weights});
  g.values()[static_cast<size_t>(depth)].name = "depth";
  g.mark_output(depth);
  nn::export_onnx(g, file);
}

void write_surface_depth_model(const std::filesystem::path& file, int width, int height) {
  nn::Graph g;
  const int image = g.add_input("image", {1, 1, height, width});
  const int prior = g.add_input("prior", {1, 3, height, width});
  nn::Attrs cat;
  cat.axis = 1;
  const int x = g.add(nn::Op::kConcat, {image, prior}, cat);
  const int weights = g.add_constant("pick_q", {{1, 4, 1, 1}, {0.f, 0.f, 0.f, 1.f}});
  const int depth = g.add(nn::Op::kConv, {x, weights});
  g.values()[static_cast<size_t>(depth)].name = "depth";
  g.mark_output(depth);
  nn::export_onnx(g, file);
}

}  // namespace pensight::testing
