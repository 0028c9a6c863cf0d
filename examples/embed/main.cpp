// A vehicle program in miniature: one pensight::Pipeline fed with a dataset's camera frames and
// DVL, pressure and attitude samples in timestamp order, as a vehicle's drivers would push them.
// Prints each frame's net-relative distance and heading and its global pose in the pen; at the
// end, how many frames gave a net pose.
#include <atomic>
#include <cstdio>
#include <exception>

#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/pipeline.h"
#include "runtime/device.h"
#include "tools/runner.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATASET\n", argv[0]);
    return 2;
  }
  try {
    const pensight::Dataset dataset = pensight::read_dataset(argv[1]);
    pensight::PipelineConfig config;
    config.camera = dataset.cam0.camera;
    config.detector.backend = pensight::Backend::kCpu;
    config.detector.bar_length_m = dataset.scene.bar_length_m;
    config.global_pose = pensight::global_pose_config(dataset);
    std::atomic<int> with_pose{0};
    config.on_frame = [&](const pensight::FrameResult& r) {  // on the pipeline's delivery thread
      with_pose += r.detection.pose.valid();
      std::printf("%lld d_net %.3f m psi_net %.2f deg r_g %.3f m\n",
                  static_cast<long long>(r.timestamp_ns), r.detection.pose.d_net_m,
                  pensight::rad_to_deg(r.detection.pose.psi_net_rad), r.global_pose.r_g_m);
    };
    config.lossless_results = true;  // a replay: wait for the printer instead of dropping
    pensight::Device device;         // one per process; every stage borrows it
    pensight::Pipeline pipeline(config, device);

    size_t dvl = 0, depth = 0;
    for (size_t i = 0; i < dataset.frames.size(); ++i) {
      const int64_t t = dataset.frames[i].timestamp_ns;
      for (; dataset.dvl0 && dvl < dataset.dvl0->samples.size() &&
             dataset.dvl0->samples[dvl].timestamp_ns <= t;
           ++dvl)
        pipeline.push(dataset.dvl0->samples[dvl]);
      for (; dataset.pressure0 && depth < dataset.pressure0->size() &&
             (*dataset.pressure0)[depth].timestamp_ns <= t;
           ++depth)
        pipeline.push((*dataset.pressure0)[depth]);
      pipeline.push(pensight::CameraFrame{t, dataset.load_frame(i)});
    }
    pipeline.finish();  // every pushed frame has been printed when this returns
    std::printf("%d of %zu frames with a pose\n", with_pose.load(), dataset.frames.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 1;
  }
  return 0;
}
