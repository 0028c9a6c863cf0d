#include "sim/generate.h"

#include <optional>

#include "core/error.h"
#include "core/log.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"
#include "sim/ground_truth.h"
#include "sim/render_vk.h"
#include "sim/sensors.h"

namespace pensight::sim {
namespace {

// Both renderers fix the net when built (the shader as specialization constants), so a scenario
// whose net changes gets a renderer of the net in view, rebuilt where the net changes.
class CpuRenderer : public FrameRenderer {
 public:
  CpuRenderer(const Scenario& s, const RenderOptions& o)
      : scenario_(s), s_(s.with_net_at(0)), net_(s_.pen, s_.net), o_(o) {}
  RenderedFrame render(const FrameState& f) override {
    const size_t net_index = scenario_.net_index_at(f.t_s);
    if (net_index != net_index_) {
      s_ = scenario_.with_net_at(f.t_s);
      net_ = NetGeometry(s_.pen, s_.net);
      net_index_ = net_index;
    }
    return render_cpu(s_, net_, f, o_);
  }
  const char* name() const override { return "cpu reference"; }

 private:
  Scenario scenario_;
  Scenario s_;  // scenario_ with the net in view
  NetGeometry net_;
  size_t net_index_ = 0;
  RenderOptions o_;
};

class VulkanRenderer : public FrameRenderer {
 public:
  VulkanRenderer(vk::Context& ctx, const Scenario& s, const RenderOptions& o)
      : ctx_(&ctx),
        scenario_(s),
        o_(o),
        vk_(std::make_unique<RenderVk>(ctx, s.with_net_at(0), o)),
        name_("vulkan (" + ctx.info().name + ")") {}
  RenderedFrame render(const FrameState& f) override {
    const size_t net_index = scenario_.net_index_at(f.t_s);
    if (net_index != net_index_) {
      vk_ = std::make_unique<RenderVk>(*ctx_, scenario_.with_net_at(f.t_s), o_);
      net_index_ = net_index;
    }
    return vk_->render(f);
  }
  const char* name() const override { return name_.c_str(); }

 private:
  vk::Context* ctx_;
  Scenario scenario_;
  RenderOptions o_;
  std::unique_ptr<RenderVk> vk_;
  size_t net_index_ = 0;
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
  // The truth of each frame is of the net in view (net_changes).
  Scenario in_view = s.with_net_at(0);
  std::optional<NetLattice> lattice;
  size_t net_index = 0;
  const int frames = s.num_frames();
  for (int i = 0; i < frames; ++i) {
    const FrameState f = frame_state(s, i);
    if (!lattice || s.net_index_at(f.t_s) != net_index) {
      net_index = s.net_index_at(f.t_s);
      in_view = s.with_net_at(f.t_s);
      lattice.emplace(in_view.net, net.u_around(), s.seed);
    }
    const RenderedFrame r = renderer.render(f);
    if (s.camera.colour) {
      writer.add_frame(f.timestamp_ns, r.image_rgb);
    } else {
      writer.add_frame(f.timestamp_ns, r.image);
    }
    writer.add_groundtruth(ground_truth_row(in_view, net, f, r.depth_m),
                           depth_mm_from_m(r.depth_m));
    writer.add_mesh_truth(mesh_truth_row(in_view, net, *lattice, f));
    if (options.progress) options.progress(i + 1, frames);
  }
  writer.finish();
}

}  // namespace pensight::sim
