#include "mapping/occupancy_map.h"

#include <cmath>
#include <limits>

#include "mapping/voxel_ray.h"

namespace pensight::mapping {
namespace {

openvdb::Vec3d to_vdb(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

}  // namespace

OccupancyMap::OccupancyMap(MapConfig config) : config_(config) {
  validate(config_);
  openvdb::initialize();
  grid_ = openvdb::FloatGrid::create(0.0f);
  grid_->setTransform(openvdb::math::Transform::createLinearTransform(config_.voxel_m));
  grid_->setName("occupancy");
}

OccupancyMap::OccupancyMap(MapConfig config, openvdb::FloatGrid::Ptr grid)
    : config_(config), grid_(std::move(grid)) {
  validate(config_);
}

float OccupancyMap::log_odds_at(const Eigen::Vector3d& p_pen) const {
  const openvdb::Coord c = grid_->transform().worldToIndexCellCentered(to_vdb(p_pen));
  return grid_->tree().getValue(c);
}

Occupancy OccupancyMap::occupancy_at(const Eigen::Vector3d& p_pen) const {
  // Compared in float, as the grid stores it and as the other queries compare: in double a voxel
  // at exactly occupied_log_odds (0.2f > 0.2) would read occupied here and not occupied there.
  const float l = log_odds_at(p_pen);
  const auto threshold = static_cast<float>(config_.occupied_log_odds);
  if (l > threshold) return Occupancy::kOccupied;
  return l < -threshold ? Occupancy::kFree : Occupancy::kUnknown;
}

std::optional<Eigen::Vector3d> OccupancyMap::first_occupied_along_ray(
    const Eigen::Vector3d& origin_pen, const Eigen::Vector3d& dir_pen,
    double max_distance_m) const {
  const double norm = dir_pen.norm();
  if (!(norm > 0) || !origin_pen.allFinite() || !dir_pen.allFinite()) return std::nullopt;
  const double v = config_.voxel_m;
  const auto threshold = static_cast<float>(config_.occupied_log_odds);
  auto acc = grid_->getConstAccessor();
  std::optional<Eigen::Vector3d> hit;
  traverse_voxels(origin_pen / v, dir_pen / norm, max_distance_m / v,
                  [&](const openvdb::Coord& c, double, double) {
                    if (acc.getValue(c) <= threshold) return true;
                    hit = Eigen::Vector3d(c.x(), c.y(), c.z()) * v;
                    return false;
                  });
  return hit;
}

double OccupancyMap::distance_to_occupied(const Eigen::Vector3d& p_pen,
                                          double max_distance_m) const {
  const double v = config_.voxel_m;
  const auto threshold = static_cast<float>(config_.occupied_log_odds);
  const Eigen::Vector3d p = p_pen / v;
  const double r = max_distance_m / v;
  const openvdb::CoordBBox box(
      openvdb::Coord(static_cast<int>(std::floor(p.x() - r)),
                     static_cast<int>(std::floor(p.y() - r)),
                     static_cast<int>(std::floor(p.z() - r))),
      openvdb::Coord(static_cast<int>(std::ceil(p.x() + r)), static_cast<int>(std::ceil(p.y() + r)),
                     static_cast<int>(std::ceil(p.z() + r))));
  using Leaf = openvdb::FloatTree::LeafNodeType;
  const openvdb::Coord lo = box.min() & ~(Leaf::DIM - 1), hi = box.max() & ~(Leaf::DIM - 1);
  auto acc = grid_->getConstAccessor();
  double best2 = r * r;
  bool found = false;
  for (int x = lo.x(); x <= hi.x(); x += Leaf::DIM) {
    for (int y = lo.y(); y <= hi.y(); y += Leaf::DIM) {
      for (int z = lo.z(); z <= hi.z(); z += Leaf::DIM) {
        const Leaf* leaf = acc.probeConstLeaf(openvdb::Coord(x, y, z));
        if (leaf == nullptr) continue;  // a tile: only free tiles are ever stored
        for (auto it = leaf->cbeginValueOn(); it; ++it) {
          if (*it <= threshold) continue;
          const openvdb::Coord c = it.getCoord();
          const double d2 = (Eigen::Vector3d(c.x(), c.y(), c.z()) - p).squaredNorm();
          if (d2 <= best2) {
            best2 = d2;
            found = true;
          }
        }
      }
    }
  }
  return found ? std::sqrt(best2) * v : std::numeric_limits<double>::infinity();
}

size_t OccupancyMap::occupied_voxel_count() const {
  const auto threshold = static_cast<float>(config_.occupied_log_odds);
  size_t n = 0;
  for (auto it = grid_->cbeginValueOn(); it; ++it) {
    if (*it > threshold) n += it.getVoxelCount();
  }
  return n;
}

size_t OccupancyMap::memory_bytes() const {
  return grid_->memUsage();
}

}  // namespace pensight::mapping
