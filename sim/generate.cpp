#include "sim/generate.h"

#include "pipeline/dataset/dataset_writer.h"
#include "runtime/error.h"
#include "sim/ground_truth.h"
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

}  // namespace

std::unique_ptr<FrameRenderer> make_cpu_renderer(const Scenario& s, const RenderOptions& o) {
  return std::make_unique<CpuRenderer>(s, o);
}

std::unique_ptr<FrameRenderer> make_renderer(const Scenario& s, const RenderOptions& o,
                                             const std::string& which) {
  if (which == "cpu" || which == "auto") return make_cpu_renderer(s, o);
  throw Error("unknown renderer '" + which + "': use auto, vulkan or cpu");
}

void generate_dataset(const Scenario& s, FrameRenderer& renderer,
                      const std::filesystem::path& out, const GenerateOptions& options) {
  const NetGeometry net(s.pen, s.net);
  DatasetContents contents;
  contents.scene = s.scene_config();
  contents.cam0 = s.camera.calibration;
  if (s.dvl.enabled) contents.dvl0 = dvl_calibration(s.dvl);
  contents.pressure0 = s.pressure.enabled;
  contents.imu0 = s.attitude.enabled;
  DatasetWriter writer(out, contents);
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
    writer.add_frame(f.timestamp_ns, r.image);
    writer.add_groundtruth(ground_truth_row(s, net, f, r.depth_m), depth_to_mm(r.depth_m));
    if (options.progress) options.progress(i + 1, frames);
  }
  writer.finish();
}

}  // namespace pensight::sim
