// scene.yaml of a dataset (read_scene_yaml), written by other tools.
#include "fuzz/fuzz_input.h"
#include "pipeline/dataset/calibration_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const auto file = pensight::fuzz::write_input(data, size, "scene.yaml");
  pensight::fuzz::expect_clean_error([&] { pensight::read_scene_yaml(file); });
  return 0;
}
