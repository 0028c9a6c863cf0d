#pragma once
// Nortek's own Nucleus 1000 recording (../shared/real/dvl/nucleus_sample.nucleus), whole, for the
// driver tests (their targets define PENSIGHT_SHARED_DIR).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace pensight::testing {

inline std::vector<uint8_t> nucleus_recording() {
  const auto file = std::filesystem::path(PENSIGHT_SHARED_DIR) / "real/dvl/nucleus_sample.nucleus";
  std::ifstream in(file, std::ios::binary);
  EXPECT_TRUE(in) << file << " is missing: the project expects ../shared/ beside its checkout";
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace pensight::testing
