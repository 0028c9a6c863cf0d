// A saved map (read_map_vdb, as `pensight map-query` loads it).
#include "fuzz/fuzz_input.h"
#include "mapping/map_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const auto file = pensight::fuzz::write_input(data, size, "map.vdb");
  pensight::fuzz::expect_clean_error([&] { pensight::mapping::read_map_vdb(file); });
  return 0;
}
