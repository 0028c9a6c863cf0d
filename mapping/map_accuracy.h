#pragma once
// How well a map reproduces a known surface (issue acceptance and docs/mapping.md): the surface
// mesh's distance to it, the share of the observed surface the mesh covers, and occupied voxels
// in front of it.
#include <Eigen/Core>

#include <functional>
#include <span>
#include <string>

#include "mapping/map_io.h"
#include "mapping/occupancy_map.h"

namespace pensight::mapping {

struct MapAccuracy {
  size_t vertices = 0;
  double median_m = 0, p95_m = 0;  // |distance| of the mesh vertices to the true surface
  size_t observed_points = 0;
  double completeness = 0;  // share of the observed points with a mesh vertex within one voxel
  size_t occupied_voxels = 0;
  double false_occupancy = 0;  // share of occupied voxels more than two voxels in front
};

// signed_distance_m: distance of a point of P to the true surface, positive on the side the
// camera sees it from. observed_pen: points of the true surface that the depth images saw.
MapAccuracy score_map(const OccupancyMap& map, const SurfaceMesh& mesh,
                      std::span<const Eigen::Vector3d> observed_pen,
                      const std::function<double(const Eigen::Vector3d&)>& signed_distance_m);

// "vertices N: median X mm (Y voxel), p95 ...; completeness ...; false occupancy ...".
std::string describe(const MapAccuracy& a, double voxel_m);

}  // namespace pensight::mapping
