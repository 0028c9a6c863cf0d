// The map YAML of `pensight map --config` (read_map_config).
#include "fuzz/fuzz_input.h"
#include "mapping/map_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const auto file = pensight::fuzz::write_input(data, size, "map.yaml");
  pensight::fuzz::expect_clean_error([&] { pensight::mapping::read_map_config(file); });
  return 0;
}
