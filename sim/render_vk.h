#pragma once
// The Vulkan renderer: shaders/sim/render.comp, the same model as render_cpu (the reference it
// is tested against). Built once per scenario: the image size, supersampling and everything the
// scenario fixes (net, water, light, lamps in the camera frame, ...) are specialization
// constants, and the lamps' veil a table uploaded once (lamp_veil_table.h); per frame only a
// small block (camera pose, fish, marine snow spots) changes.
#include <memory>

#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"
#include "sim/frame_state.h"
#include "sim/render_cpu.h"

namespace pensight::sim {

class RenderVk {
 public:
  RenderVk(const vk::Context& ctx, const Scenario& s, const RenderOptions& options = {});

  // The per-frame inputs of the shader: `frame` for the frame buffer (camera pose, fish, snow
  // spots), `tiles` for the tile buffer (the spots of each 8x8 pixel tile). Their sizes vary
  // with the number of snow spots in view.
  struct FrameData {
    std::vector<uint8_t> frame;
    std::vector<uint32_t> tiles;
  };
  FrameData frame_data(const FrameState& f) const;

  // frame, tiles: at least as large as a FrameData's upload (uploaded before each submission);
  // image: float[w*h] grey levels 0..255 (quantised, noise included; with radiance_only or any
  // optics key the unrounded noise-free radiance, RenderedFrame::radiance); depth: float[w*h] net
  // z-depth in metres, 0 = no net.
  void record(vk::CommandStream& stream, const vk::Buffer& frame, const vk::Buffer& tiles,
              const vk::Buffer& image, const vk::Buffer& depth) const;

  // Convenience with buffers and a recorded stream kept between calls (grown and re-recorded
  // when a frame has more snow than any before): upload, run, download, and the optics
  // (optics.h) on the CPU where the scenario asks for them.
  RenderedFrame render(const FrameState& f);

  int width() const;
  int height() const;

 private:
  const vk::Context* ctx_;
  Scenario s_;
  RenderOptions options_;
  const vk::Pipeline* pipeline_;            // borrowed from the context's registry
  std::shared_ptr<const vk::Buffer> veil_;  // lamp_veil_table.h, read by every frame
  struct Resources;
  std::shared_ptr<Resources> res_;  // created on the first render()
};

}  // namespace pensight::sim
