// The scenario YAML of `pensight render` (parse_scenario), strict: a typo is an error.
#include <string>

#include "fuzz/fuzz_input.h"
#include "sim/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pensight::fuzz::quiet_log();
  const std::string text(reinterpret_cast<const char*>(data), size);
  pensight::fuzz::expect_clean_error([&] { pensight::sim::parse_scenario(text, "fuzz.yaml"); });
  return 0;
}
