// cam0/sensor.yaml of a dataset (read_camera_yaml), written by other tools.
#include "fuzz/fuzz_input.h"
#include "pipeline/dataset/calibration_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const auto file = pensight::fuzz::write_input(data, size, "cam0/sensor.yaml");
  pensight::fuzz::expect_clean_error([&] { pensight::read_camera_yaml(file); });
  return 0;
}
