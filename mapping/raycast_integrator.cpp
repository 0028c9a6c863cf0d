#include "mapping/raycast_integrator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "mapping/voxel_ray.h"

namespace pensight::mapping {

RaycastIntegrator::RaycastIntegrator(const PinholeCamera& camera, const MapConfig& config)
    : camera_(camera), config_(config) {
  validate(config_);
  if (camera_.has_distortion()) {
    throw Error(
        "raycast integrator: the depth camera has lens distortion; give it an undistorted "
        "(pinhole) depth image and camera");
  }
}

IntegrationStats RaycastIntegrator::integrate(OccupancyMap& map, const ImageF32& depth_m,
                                              const Eigen::Isometry3d& T_pen_camera) {
  IntegrationStats stats;
  check_image_size(depth_m.width, depth_m.height, camera_, "raycast integrator", "depth image");
  if (map.config().voxel_m != config_.voxel_m) {
    throw Error("raycast integrator: the map's voxel is " + std::to_string(map.config().voxel_m) +
                " m, the integrator's " + std::to_string(config_.voxel_m) + " m");
  }
  if (!T_pen_camera.matrix().allFinite()) return stats;
  stats.integrated = true;

  // Index space: voxel c spans [c - 0.5, c + 0.5) per axis, as in OccupancyMap.
  const double v = config_.voxel_m;
  const Eigen::Vector3d origin = T_pen_camera.translation() / v;
  openvdb::MaskTree hits, misses;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> hit_acc(hits), miss_acc(misses);
  for (int y = 0; y < depth_m.height; ++y) {
    for (int x = 0; x < depth_m.width; ++x) {
      const float d = depth_m.at(x, y);
      if (!(d >= config_.min_range_m)) continue;  // 0, NaN, negative, too near: unknown
      const bool beyond = d > config_.max_range_m;
      const double z_m = beyond ? config_.max_range_m : d;
      const Eigen::Vector3d end = T_pen_camera * (camera_.ray(Eigen::Vector2d(x, y)) * z_m) / v;
      const openvdb::Coord end_voxel(static_cast<int>(std::floor(end.x() + 0.5)),
                                     static_cast<int>(std::floor(end.y() + 0.5)),
                                     static_cast<int>(std::floor(end.z() + 0.5)));
      traverse_voxels(origin, end - origin, 1.0, [&](const openvdb::Coord& c, double, double) {
        if (c == end_voxel) return false;
        miss_acc.setValueOn(c);
        return true;
      });
      if (!beyond) hit_acc.setValueOn(end_voxel);
    }
  }
  misses.topologyDifference(hits);  // a voxel both hit and crossed counts as hit
  stats.hit_voxels = hits.activeVoxelCount();

  const auto hit = static_cast<float>(config_.hit_log_odds);
  const auto miss = static_cast<float>(config_.miss_log_odds);
  const auto min_lo = static_cast<float>(config_.min_log_odds);
  const auto max_lo = static_cast<float>(config_.max_log_odds);
  auto acc = map.grid().getAccessor();
  for (auto it = hits.cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    acc.setValueOn(c, std::min(acc.getValue(c) + hit, max_lo));
  }
  for (auto it = misses.cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    acc.setValueOn(c, std::max(acc.getValue(c) + miss, min_lo));
  }
  return stats;
}

}  // namespace pensight::mapping
