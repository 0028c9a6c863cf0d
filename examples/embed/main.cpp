// Reads a dataset folder and runs the FFT net detection on the CPU on each frame, printing the
// net-relative distance and heading; at the end, how many frames gave a pose.
#include <cstdio>
#include <exception>
#include <numbers>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/net_detector.h"
#include "runtime/device.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATASET\n", argv[0]);
    return 2;
  }
  try {
    const pensight::Dataset dataset = pensight::read_dataset(argv[1]);
    pensight::NetDetectorConfig config;
    config.backend = pensight::Backend::kCpu;
    config.mesh_m = dataset.scene.net_mesh_size_m;
    pensight::Device device;  // one per process; the CPU backend opens nothing on it
    pensight::NetDetector detector(dataset.cam0.camera, config, device);

    int with_pose = 0;
    for (size_t i = 0; i < dataset.frames.size(); ++i) {
      const int64_t t = dataset.frames[i].timestamp_ns;
      const pensight::NetDetection d = detector.detect(dataset.load_frame(i), t);
      if (d.pose.valid()) ++with_pose;
      std::printf("%lld d_net %.3f m psi_net %.2f deg\n", static_cast<long long>(t), d.pose.d_net_m,
                  d.pose.psi_net_rad * 180.0 / std::numbers::pi);
    }
    std::printf("%d of %zu frames with a pose\n", with_pose, dataset.frames.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 1;
  }
  return 0;
}
