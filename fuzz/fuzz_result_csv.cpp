// The result files that `pensight evaluate` reads back, possibly from other tools: estimates.csv,
// global_pose.csv and TUM trajectories. The first byte picks the reader.
#include "fuzz/fuzz_input.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "pipeline/dataset/trajectory_tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  pensight::fuzz::quiet_log();
  const auto file = pensight::fuzz::write_input(data + 1, size - 1, "result.csv");
  pensight::fuzz::expect_clean_error([&] {
    switch (data[0] % 3) {
      case 0:
        pensight::read_estimates_csv(file);
        break;
      case 1:
        pensight::read_global_pose_csv(file);
        break;
      default:
        pensight::read_trajectory_tum(file);
        break;
    }
  });
  return 0;
}
