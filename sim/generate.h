#pragma once
// A scenario rendered into a dataset in the layout of dataset-format.md: cam0 frames,
// groundtruth0 rows with depth images, and the dvl0 / pressure0 / imu0 streams.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "pipeline/dataset/dataset_writer.h"
#include "runtime/device.h"
#include "sim/frame_state.h"
#include "sim/render_cpu.h"

namespace pensight::sim {

// Renders frames of one scenario; the CPU reference or the Vulkan renderer.
class FrameRenderer {
 public:
  virtual ~FrameRenderer() = default;
  virtual RenderedFrame render(const FrameState& f) = 0;
  virtual const char* name() const = 0;
};

std::unique_ptr<FrameRenderer> make_cpu_renderer(const Scenario& s, const RenderOptions& o);
// The renderer on `backend`: kCpu the C++ reference, kVulkan the shader, kAuto the shader on any
// Vulkan device (lavapipe too: about 2x the C++ reference on the same cores, docs/performance.md),
// else the reference; kCuda is refused (no CUDA renderer). The Vulkan renderer borrows device's
// context, which must outlive it.
std::unique_ptr<FrameRenderer> make_renderer(const Scenario& s, const RenderOptions& o,
                                             Backend backend, Device& device);

// What a dataset of the scenario holds: its scene, camera, and the sensors it has enabled.
DatasetContents dataset_contents(const Scenario& s);

struct GenerateOptions {
  std::function<void(int frames_done, int frames_total)> progress;
};

// Writes the dataset to `out` (replacing an earlier dataset there, never any other folder);
// nothing appears under `out` unless every frame was written.
void generate_dataset(const Scenario& s, FrameRenderer& renderer, const std::filesystem::path& out,
                      const GenerateOptions& options = {});

}  // namespace pensight::sim
