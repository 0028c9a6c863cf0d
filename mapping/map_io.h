#pragma once
// Map files (../shared/dataset-format.md): OUT/map.vdb (OpenVDB FloatGrid "occupancy", log-odds,
// P frame, metres, the MapConfig in the grid's metadata), OUT/map_mesh.ply (the surface at
// log-odds occupied_log_odds, tools::volumeToMesh) and OUT/map_points.ply (occupied voxel
// centres). Every file is written whole (to a temporary name, then renamed).
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <vector>

#include "mapping/occupancy_map.h"

namespace pensight::mapping {

struct SurfaceMesh {
  std::vector<Eigen::Vector3f> vertices;  // P, metres
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<std::array<uint32_t, 4>> quads;
};

// The boundary between occupied voxels and the rest (tools::volumeToMesh at isovalue
// occupied_log_odds on the negated log-odds, so occupied is inside). Cost: one pass over the
// active leaves.
SurfaceMesh extract_surface(const OccupancyMap& map);

// Throws pensight::Error naming the file when it cannot be written.
void write_map_vdb(const OccupancyMap& map, const std::filesystem::path& file);
// Throws pensight::Error naming the file when it is missing, not an OpenVDB file, or has no
// FloatGrid named "occupancy" with a uniform voxel size; MapConfig keys absent from its metadata
// keep their defaults.
OccupancyMap read_map_vdb(const std::filesystem::path& file);

// The three map outputs into `dir`: map.vdb, map_mesh.ply, map_points.ply. Returns the mesh.
SurfaceMesh write_map_outputs(const OccupancyMap& map, const std::filesystem::path& dir);

// Binary little-endian PLY (vertex x, y, z as float; faces as uchar-counted uint lists).
void write_mesh_ply(const SurfaceMesh& mesh, const std::filesystem::path& file);
void write_points_ply(const OccupancyMap& map, const std::filesystem::path& file);

// The centres of the occupied voxels (above occupied_log_odds), in P; one pass over the active
// values, tiles expanded to their voxels.
std::vector<Eigen::Vector3f> occupied_voxel_centres(const OccupancyMap& map);

}  // namespace pensight::mapping
