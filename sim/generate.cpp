#include "sim/generate.h"

#include "core/error.h"
#include "core/log.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"
#include "sim/ground_truth.h"
#include "sim/render_vk.h"
#include "sim/sensors.h"

namespace pensight::sim {
namespace {

class CpuRenderer : public FrameRenderer {
 public:
  CpuRenderer(const Scenario& s, const RenderOptions& o) : s_(s), net_(s.pen, s.net), o_(o) {}
  RenderedFrame render(const FrameState& f) override { return render_cpu(s_, net_, f, o_); }
  const char* name() const override { return "cpu reference"; }

 private:
  Scenario s_;
  NetGeometry net_;
  RenderOptions o_;
};

class VulkanRenderer : public FrameRenderer {
 public:
  VulkanRenderer(vk::Context& ctx, const Scenario& s, const RenderOptions& o)
      : vk_(ctx, s, o), name_("vulkan (" + ctx.info().name + ")") {}
  RenderedFrame render(const FrameState& f) override { return vk_.render(f); }
  const char* name() const override { return name_.c_str(); }

 private:
  RenderVk vk_;
  std::string name_;
};

}  // namespace

std::unique_ptr<FrameRenderer> make_cpu_renderer(const Scenario& s, const RenderOptions& o) {
  return std::make_unique<CpuRenderer>(s, o);
}

std::unique_ptr<FrameRenderer> make_renderer(const Scenario& s, const RenderOptions& o,
                                             Backend backend, Device& device) {
  switch (choose_backend(backend, device, {.software_vulkan = true})) {
    case Backend::kVulkan:
      return std::make_unique<VulkanRenderer>(device.vulkan(), s, o);
    case Backend::kCuda:
      throw Error("the renderer has no CUDA path; use --renderer vulkan or cpu");
    case Backend::kCpu:
    case Backend::kAuto:
      break;
  }
  if (backend == Backend::kAuto) {
    log_warning("no Vulkan renderer (" + device.vulkan_error() + "); using the CPU reference");
  }
  return make_cpu_renderer(s, o);
}

DatasetContents dataset_contents(const Scenario& s) {
  DatasetContents contents;
  contents.scene = s.scene_config();
  contents.cam0 = s.camera.calibration;
  if (s.dvl.enabled) contents.dvl0 = dvl_calibration(s.dvl);
  contents.pressure0 = s.pressure.enabled;
  contents.imu0 = s.attitude.enabled;
  return contents;
}

void generate_dataset(const Scenario& s, FrameRenderer& renderer, const std::filesystem::path& out,
                      const GenerateOptions& options) {
  const NetGeometry net(s.pen, s.net);
  const NetLattice lattice(s.net, net.u_around(), s.seed);
  DatasetWriter writer(out, dataset_contents(s));
  if (s.dvl.enabled) {
    for (const DvlSample& d : simulate_dvl(s, net)) writer.add_dvl(d);
  }
  if (s.pressure.enabled) {
    for (const PressureSample& p : simulate_pressure(s)) writer.add_pressure(p);
  }
  if (s.attitude.enabled) {
    for (const AttitudeSample& a : simulate_attitude(s)) writer.add_attitude(a);
  }
  const int frames = s.num_frames();
  for (int i = 0; i < frames; ++i) {
    const FrameState f = frame_state(s, i);
    const RenderedFrame r = renderer.render(f);
    if (s.camera.colour) {
      writer.add_frame(f.timestamp_ns, r.image_rgb);
    } else {
      writer.add_frame(f.timestamp_ns, r.image);
    }
    writer.add_groundtruth(ground_truth_row(s, net, f, r.depth_m), depth_mm_from_m(r.depth_m));
    writer.add_mesh_truth(mesh_truth_row(s, net, lattice, f));
    if (options.progress) options.progress(i + 1, frames);
  }
  writer.finish();
}

}  // namespace pensight::sim
