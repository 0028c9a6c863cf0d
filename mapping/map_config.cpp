#include "mapping/map_config.h"

#include <string>

#include "core/error.h"
#include "core/strict_yaml.h"

namespace pensight::mapping {
namespace {

// Beyond 1-5 cm the map is too coarse to place a twine or too fine for the depth's noise; the
// log-odds bounds keep every update and clamp of the right sign and finite.
const Param<MapConfig> kMapParams[] = {
    {"voxel_m", &MapConfig::voxel_m, "m", closed_range(0.01, 0.05), "voxel edge"},
    {"hit_log_odds", &MapConfig::hit_log_odds, "", closed_range(1e-3, 10),
     "added where a depth ends (0.85: p = 0.7)"},
    {"miss_log_odds", &MapConfig::miss_log_odds, "", closed_range(-10, -1e-3),
     "added where a ray passes (-0.4: p = 0.4)"},
    {"min_log_odds", &MapConfig::min_log_odds, "", closed_range(-20, -1e-3),
     "lower clamp: a voxel saturated free turns occupied after 3 hits"},
    {"max_log_odds", &MapConfig::max_log_odds, "", closed_range(1e-3, 20),
     "upper clamp: a voxel saturated occupied clears after 9 misses"},
    {"occupied_log_odds", &MapConfig::occupied_log_odds, "", closed_range(0, 20),
     "above: occupied, below its negative: free (at most max_log_odds)"},
    {"min_range_m", &MapConfig::min_range_m, "m", closed_range(0, 100), "nearest depth used"},
    {"max_range_m", &MapConfig::max_range_m, "m", closed_range(0, 100),
     "farthest depth used; beyond it a pixel clears up to it and adds no hit"},
    {"free_margin_m", &MapConfig::free_margin_m, "m", closed_range(0, 1),
     "a voxel is free only this far in front of every depth in its footprint"},
    {"threads", &MapConfig::threads, "", closed_range(0, 256),
     "TBB workers of one integration (0: one per core)"},
};

constexpr const char* kWhere = "map config";

}  // namespace

std::span<const Param<MapConfig>> map_params() {
  return kMapParams;
}

void validate(const MapConfig& c) {
  check_params(c, map_params(), kWhere);
  if (!(c.occupied_log_odds <= c.max_log_odds)) {
    throw Error(std::string(kWhere) +
                ": key 'occupied_log_odds': " + format_param_value(c.occupied_log_odds) +
                " is above max_log_odds (" + format_param_value(c.max_log_odds) + ")");
  }
  if (!(c.max_range_m >= c.min_range_m + c.voxel_m)) {
    throw Error(std::string(kWhere) + ": key 'max_range_m': " + format_param_value(c.max_range_m) +
                " m is not a voxel beyond min_range_m (" + format_param_value(c.min_range_m) +
                " m)");
  }
}

MapConfig read_map_config(const std::filesystem::path& file) {
  const YamlMap y = YamlMap::load_file(file);
  MapConfig c;
  read_params(y, map_params(), c);
  y.check_unknown_keys();
  try {
    validate(c);
  } catch (const Error& e) {
    throw Error(file.string() + ": " + e.what());
  }
  return c;
}

}  // namespace pensight::mapping
