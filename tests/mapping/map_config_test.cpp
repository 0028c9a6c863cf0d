// read_map_config: every key, defaults for absent keys, and errors that name the file and key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "mapping/map_config.h"

namespace pensight::mapping {
namespace {

namespace fs = std::filesystem;

class MapConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pensight_map_config_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& yaml) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << yaml;
    return file;
  }
  // Reading `yaml` throws an error that names the file and every one of `names`.
  void expect_error(const std::string& name, const std::string& yaml,
                    std::initializer_list<const char*> names) {
    const fs::path file = write(name, yaml);
    try {
      read_map_config(file);
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file.string()), std::string::npos) << m;
      for (const char* n : names) EXPECT_NE(m.find(n), std::string::npos) << m;
    }
  }

  fs::path dir_;
};

TEST_F(MapConfigTest, ReadsEveryKey) {
  const MapConfig c = read_map_config(write("all.yaml",
                                            "voxel_m: 0.03\n"
                                            "hit_log_odds: 0.9\n"
                                            "miss_log_odds: -0.35\n"
                                            "min_log_odds: -1.8\n"
                                            "max_log_odds: 3.2\n"
                                            "occupied_log_odds: 0.1\n"
                                            "min_range_m: 0.25\n"
                                            "max_range_m: 4.5\n"
                                            "free_margin_m: 0.02\n"));
  EXPECT_EQ(c.voxel_m, 0.03);
  EXPECT_EQ(c.hit_log_odds, 0.9);
  EXPECT_EQ(c.miss_log_odds, -0.35);
  EXPECT_EQ(c.min_log_odds, -1.8);
  EXPECT_EQ(c.max_log_odds, 3.2);
  EXPECT_EQ(c.occupied_log_odds, 0.1);
  EXPECT_EQ(c.min_range_m, 0.25);
  EXPECT_EQ(c.max_range_m, 4.5);
  EXPECT_EQ(c.free_margin_m, 0.02);
}

TEST_F(MapConfigTest, AbsentKeysKeepTheirDefaults) {
  const MapConfig c = read_map_config(write("some.yaml", "voxel_m: 0.04\nmax_range_m: 3\n"));
  MapConfig expected;
  expected.voxel_m = 0.04;
  expected.max_range_m = 3.0;
  EXPECT_TRUE(c == expected);
}

TEST_F(MapConfigTest, ErrorsNameTheFileAndKey) {
  expect_error("unknown.yaml", "voxel_m: 0.02\nvoxel_size: 0.02\n", {"voxel_size"});
  expect_error("type.yaml", "voxel_m: two centimetres\n", {"voxel_m"});
  try {
    read_map_config(dir_ / "missing_file.yaml");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing_file.yaml"), std::string::npos) << e.what();
  }
}

TEST_F(MapConfigTest, OutOfRangeValuesNameTheParameter) {
  expect_error("fine_voxel.yaml", "voxel_m: 0.005\n", {"voxel_m"});
  expect_error("coarse_voxel.yaml", "voxel_m: 0.06\n", {"voxel_m"});
  expect_error("nan_voxel.yaml", "voxel_m: .nan\n", {"voxel_m"});
  expect_error("ranges.yaml", "min_range_m: 2.0\nmax_range_m: 1.0\n", {"max_range_m"});
  expect_error("miss.yaml", "miss_log_odds: 0.4\n", {"miss_log_odds"});
  expect_error("hit.yaml", "hit_log_odds: 0\n", {"hit_log_odds"});
  expect_error("min.yaml", "min_log_odds: 0.5\n", {"min_log_odds"});
  expect_error("max.yaml", "max_log_odds: -1\n", {"max_log_odds"});
  expect_error("occupied.yaml", "occupied_log_odds: 4\n", {"occupied_log_odds"});
  expect_error("min_range.yaml", "min_range_m: -0.1\n", {"min_range_m"});
  expect_error("margin.yaml", "free_margin_m: -0.01\n", {"free_margin_m"});
}

TEST_F(MapConfigTest, ValidateNamesTheParameter) {
  MapConfig c;
  c.miss_log_odds = 0.1;
  try {
    validate(c);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("miss_log_odds"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(validate(MapConfig{}));
}

}  // namespace
}  // namespace pensight::mapping
