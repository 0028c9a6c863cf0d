#pragma once
// Parameters of the occupancy map (map_params() defines each key; docs/parameters.md lists them).
// Log-odds L = ln(p / (1 - p)); an unobserved voxel is unknown (inactive, L = 0), not free.
#include <filesystem>
#include <span>

#include "core/params.h"

namespace pensight::mapping {

struct MapConfig {
  double voxel_m = 0.02;  // voxel edge, 0.01-0.05 m
  // Per-frame updates. A hit (+0.85, p = 0.7) outweighs a miss (-0.4, p = 0.4), so a twine seen in
  // one frame out of three stays occupied while the water around it clears.
  double hit_log_odds = 0.85;
  double miss_log_odds = -0.4;
  // Clamps: a voxel saturated free turns occupied again after 3 hits (2.0 / 0.85), a saturated
  // occupied one clears after 9 misses (3.5 / 0.4).
  double min_log_odds = -2.0;
  double max_log_odds = 3.5;
  // Above this a voxel is occupied, below its negative free, between unknown.
  double occupied_log_odds = 0.0;
  // Depths (z along the optical axis) taken from the depth image; a pixel beyond max_range_m
  // clears the space up to max_range_m and adds no hit.
  double min_range_m = 0.1;
  double max_range_m = 5.0;
  // A voxel is free only when its nearest point lies this far in front of every depth in its
  // pixel footprint (0: in front at all); a margin of the depth noise keeps a noisy surface from
  // clearing itself.
  double free_margin_m = 0.0;
  // Worker threads of one integration (TBB); 0: one per core.
  int threads = 0;

  bool operator==(const MapConfig&) const = default;
};

// Key, unit, valid range and help of every MapConfig member; the defaults are the members'.
std::span<const Param<MapConfig>> map_params();

// Throws pensight::Error naming the parameter and its allowed range when one is out of range.
void validate(const MapConfig& config);

// Reads a map YAML (keys as MapConfig's members; absent keys keep their defaults). Throws
// pensight::Error naming the file and key for a missing file, bad YAML, an unknown key or a value
// out of range.
MapConfig read_map_config(const std::filesystem::path& file);

}  // namespace pensight::mapping
