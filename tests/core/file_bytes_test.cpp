#include "core/file_bytes.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <string>

#include "tests/support/test_seed.h"

namespace pensight {
namespace {

namespace fs = std::filesystem;

TEST(FileBytes, RoundTripsEveryByteValueAndTheEmptyFile) {
  const fs::path dir = fs::temp_directory_path() / ("pensight_bytes_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(testing::fresh_seed());
  std::string bytes(70000, '\0');  // longer than a stream buffer, with NULs and 0xff
  for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
  std::ofstream(dir / "random.bin", std::ios::binary) << bytes;
  std::ofstream(dir / "empty.bin", std::ios::binary).close();
  EXPECT_EQ(read_file_bytes(dir / "random.bin"), bytes);
  EXPECT_EQ(read_file_bytes(dir / "empty.bin"), std::string());
  fs::remove_all(dir);
}

TEST(FileBytes, MissingFileOrFolderIsNothing) {
  const fs::path dir = fs::temp_directory_path() / ("pensight_bytes_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_EQ(read_file_bytes(dir / "missing.bin"), std::nullopt);
  EXPECT_EQ(read_file_bytes(dir), std::nullopt);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pensight
