#pragma once
// The occupancy map: an OpenVDB FloatGrid of log-odds in the pen frame P (metres), voxel centres
// at integer multiples of the voxel size. Unobserved voxels are inactive (log-odds 0, unknown);
// observed ones are active. Whole 8^3 leaves saturated free are stored as tiles
// (projective_integrator.h), so open water costs one value per leaf.
//
// Queries are free of side effects and thread-safe against each other (not against integration).
#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include <optional>

#include "mapping/map_config.h"

namespace pensight::mapping {

enum class Occupancy { kUnknown, kFree, kOccupied };

class OccupancyMap {
 public:
  // Throws pensight::Error for a config out of range (validate()).
  explicit OccupancyMap(MapConfig config);
  // Takes a loaded grid (map_io.h) with the config it was built with.
  OccupancyMap(MapConfig config, openvdb::FloatGrid::Ptr grid);

  const MapConfig& config() const { return config_; }
  openvdb::FloatGrid& grid() { return *grid_; }
  const openvdb::FloatGrid& grid() const { return *grid_; }

  // Log-odds of the voxel holding p_pen (0 where unknown).
  float log_odds_at(const Eigen::Vector3d& p_pen) const;
  // kOccupied above occupied_log_odds, kFree below its negative, else kUnknown.
  Occupancy occupancy_at(const Eigen::Vector3d& p_pen) const;

  // Centre of the first occupied voxel that the ray origin + t * dir (dir need not be unit)
  // enters within max_distance_m of the origin (voxel traversal, Amanatides & Woo 1987); the
  // voxel holding the origin counts. Costs one lookup per voxel crossed.
  std::optional<Eigen::Vector3d> first_occupied_along_ray(const Eigen::Vector3d& origin_pen,
                                                          const Eigen::Vector3d& dir_pen,
                                                          double max_distance_m) const;

  // Distance from p_pen to the nearest occupied voxel centre, +inf when there is none within
  // max_distance_m. Visits the leaves within max_distance_m (a cube of side 2 * max_distance_m).
  double distance_to_occupied(const Eigen::Vector3d& p_pen, double max_distance_m) const;

  // Voxels that are occupied, and the grid's memory (OpenVDB's own count).
  size_t occupied_voxel_count() const;
  size_t memory_bytes() const;

 private:
  MapConfig config_;
  openvdb::FloatGrid::Ptr grid_;
};

}  // namespace pensight::mapping
