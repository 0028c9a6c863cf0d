#include "mapping/map_config.h"

#include <cmath>
#include <string>

#include "pipeline/dataset/strict_yaml.h"
#include "runtime/error.h"

namespace pensight::mapping {
namespace {

void check_range(const char* name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    throw Error("map config: " + std::string(name) + " = " + std::to_string(value) +
                " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
}

}  // namespace

void validate(const MapConfig& c) {
  check_range("voxel_m", c.voxel_m, 0.01, 0.05);
  check_range("hit_log_odds", c.hit_log_odds, 1e-3, 10);
  check_range("miss_log_odds", c.miss_log_odds, -10, -1e-3);
  check_range("max_log_odds", c.max_log_odds, 1e-3, 20);
  check_range("min_log_odds", c.min_log_odds, -20, -1e-3);
  check_range("occupied_log_odds", c.occupied_log_odds, 0, c.max_log_odds);
  check_range("min_range_m", c.min_range_m, 0, 100);
  check_range("max_range_m", c.max_range_m, c.min_range_m + c.voxel_m, 100);
  check_range("free_margin_m", c.free_margin_m, 0, 1);
  check_range("threads", c.threads, 0, 256);
}

MapConfig read_map_config(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file);
  MapConfig c;
  c.voxel_m = y.number("voxel_m", c.voxel_m);
  c.hit_log_odds = y.number("hit_log_odds", c.hit_log_odds);
  c.miss_log_odds = y.number("miss_log_odds", c.miss_log_odds);
  c.min_log_odds = y.number("min_log_odds", c.min_log_odds);
  c.max_log_odds = y.number("max_log_odds", c.max_log_odds);
  c.occupied_log_odds = y.number("occupied_log_odds", c.occupied_log_odds);
  c.min_range_m = y.number("min_range_m", c.min_range_m);
  c.max_range_m = y.number("max_range_m", c.max_range_m);
  c.free_margin_m = y.number("free_margin_m", c.free_margin_m);
  c.threads = y.integer("threads", c.threads);
  y.check_unknown_keys();
  try {
    validate(c);
  } catch (const Error& e) {
    throw Error(file.string() + ": " + e.what());
  }
  return c;
}

}  // namespace pensight::mapping
