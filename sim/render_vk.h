#pragma once
// The Vulkan renderer: shaders/sim/render.comp, one invocation per pixel, the same model as
// render_cpu (the reference it is tested against). Built once per scenario (image size and
// supersampling are specialization constants); per frame only a small parameter block changes.
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

  // Bytes of the parameter block that params(f) fills.
  static size_t params_bytes();
  // Parameter block of frame f (upload it into the buffer passed to record()).
  std::vector<uint8_t> params(const FrameState& f) const;
  // params: params_bytes(); image: float[w*h] grey levels 0..255 (quantised, noise included);
  // depth: float[w*h] net z-depth in metres, 0 = no net.
  void record(vk::CommandStream& stream, const vk::Buffer& params, const vk::Buffer& image,
              const vk::Buffer& depth) const;

  // Convenience with buffers and a recorded stream kept between calls: upload, run, download.
  RenderedFrame render(const FrameState& f);

  int width() const;
  int height() const;

 private:
  const vk::Context* ctx_;
  Scenario s_;
  RenderOptions options_;
  vk::Pipeline pipeline_;
  struct Resources;
  std::shared_ptr<Resources> res_;  // created on the first render()
};

}  // namespace pensight::sim
