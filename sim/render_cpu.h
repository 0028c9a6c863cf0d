#pragma once
// The camera image and ground-truth depth of one frame, rendered on the CPU. This is the
// reference the Vulkan renderer (render_vk.h) is tested against; docs/sim.md describes the model.
#include "core/image.h"
#include "sim/frame_state.h"
#include "sim/net_geometry.h"

namespace pensight::sim {

struct RenderOptions {
  bool noise = true;        // sensor noise (off for comparisons and geometry tests)
  bool marine_snow = true;  // suspended particles
  // Only the grey radiance before the camera's optics and sensor (RenderedFrame::radiance): no
  // defocus, motion blur, colour, noise, rounding or JPEG.
  bool radiance_only = false;
};

struct RenderedFrame {
  ImageU8 image;        // the grey frame; empty with camera.colour or radiance_only
  ImageRgb8 image_rgb;  // camera.colour: the colour frame
  // radiance_only, or on the way through the optics (sim/optics.h): exposure x 255 x radiance
  // (vignetting and marine snow included), unrounded grey levels.
  ImageF32 radiance;
  // z-depth in the camera frame of the net seen by each pixel's centre ray, 0 where the pixel
  // sees no net (water, surface, fish, or net beyond net_visible_range_m).
  ImageF32 depth_m;
};

// Distance beyond which the net counts as not seen: where water leaves 2% of its contrast.
double net_visible_range_m(const WaterConfig& water);

RenderedFrame render_cpu(const Scenario& s, const NetGeometry& net, const FrameState& f,
                         const RenderOptions& options = {});

}  // namespace pensight::sim
