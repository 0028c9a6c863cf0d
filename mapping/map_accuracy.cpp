#include "mapping/map_accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>
#include <vector>

#include "core/units.h"
#include "tools/evaluation/evaluation.h"

namespace pensight::mapping {
namespace {

struct CellHash {
  size_t operator()(const Eigen::Vector3i& c) const {
    return static_cast<size_t>(c.x()) * 73856093u ^ static_cast<size_t>(c.y()) * 19349663u ^
           static_cast<size_t>(c.z()) * 83492791u;
  }
};

}  // namespace

MapAccuracy score_map(const OccupancyMap& map, const SurfaceMesh& mesh,
                      std::span<const Eigen::Vector3d> observed_pen,
                      const std::function<double(const Eigen::Vector3d&)>& signed_distance_m) {
  const double v = map.config().voxel_m;
  MapAccuracy a;
  a.vertices = mesh.vertices.size();
  std::vector<double> errors;
  errors.reserve(mesh.vertices.size());
  // Vertices bucketed by voxel, so a point's nearest vertex within one voxel is in the 27 around.
  std::unordered_map<Eigen::Vector3i, std::vector<Eigen::Vector3f>, CellHash> buckets;
  for (const Eigen::Vector3f& p : mesh.vertices) {
    errors.push_back(std::abs(signed_distance_m(p.cast<double>())));
    buckets[(p.cast<double>() / v).array().floor().cast<int>().matrix()].push_back(p);
  }
  const ErrorStats e = error_stats(errors);
  a.median_m = e.count ? e.median : kNaN;
  a.p95_m = e.count ? e.p95 : kNaN;

  a.observed_points = observed_pen.size();
  size_t covered = 0;
  const auto v2 = static_cast<float>(v * v);
  for (const Eigen::Vector3d& q : observed_pen) {
    const Eigen::Vector3i c = (q / v).array().floor().cast<int>().matrix();
    const Eigen::Vector3f qf = q.cast<float>();
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx) {
      for (int dy = -1; dy <= 1 && !near; ++dy) {
        for (int dz = -1; dz <= 1 && !near; ++dz) {
          const auto it = buckets.find(c + Eigen::Vector3i(dx, dy, dz));
          if (it == buckets.end()) continue;
          for (const Eigen::Vector3f& p : it->second) {
            if ((p - qf).squaredNorm() <= v2) {
              near = true;
              break;
            }
          }
        }
      }
    }
    covered += near;
  }
  a.completeness = observed_pen.empty() ? kNaN : double(covered) / double(observed_pen.size());

  size_t in_front = 0;
  const auto threshold = static_cast<float>(map.config().occupied_log_odds);
  for (auto it = map.grid().cbeginValueOn(); it; ++it) {
    if (*it <= threshold) continue;
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (const openvdb::Coord& c : box) {
      ++a.occupied_voxels;
      in_front += signed_distance_m(Eigen::Vector3d(c.x(), c.y(), c.z()) * v) > 2 * v;
    }
  }
  a.false_occupancy = a.occupied_voxels ? double(in_front) / double(a.occupied_voxels) : 0.0;
  return a;
}

std::string describe(const MapAccuracy& a, double voxel_m) {
  char line[400];
  std::snprintf(line, sizeof line,
                "mesh vertices %zu: median %.1f mm (%.2f voxel), p95 %.1f mm (%.2f voxel); "
                "completeness %.1f %% of %zu observed points; false occupancy %.2f %% of %zu "
                "occupied voxels",
                a.vertices, a.median_m * 1e3, a.median_m / voxel_m, a.p95_m * 1e3,
                a.p95_m / voxel_m, 100 * a.completeness, a.observed_points, 100 * a.false_occupancy,
                a.occupied_voxels);
  return line;
}

}  // namespace pensight::mapping
