#pragma once
// Projective occupancy integration of one depth image per call, per 8^3 leaf (the method of
// voxblox's and wavemap's projective integrators, on an OpenVDB tree):
// - hits: every pixel with a depth in [min_range_m, max_range_m] adds a hit to the voxel holding
//   its back-projected point (once per voxel and frame), so a twine thinner than a voxel, seen by
//   a few pixels next to a hole, stays occupied;
// - misses: a voxel whose whole pixel footprint is valid and lies beyond its farthest point (by
//   free_margin_m) is free; blocks are classified coarse-to-fine from 64^3 voxels down to leaves
//   against a min/max pyramid of the depth image (depth_pyramid.h), so whole blocks of open water
//   are cleared without visiting their voxels one by one: a free leaf that is not stored (unknown
//   or free water) stays a tile of one value, and one already saturated free is skipped;
// - everything else (behind a surface, outside the image, in a footprint with a hole) is left
//   unknown, never cleared; so are the voxels cut by the image border in border leaves beyond
//   2.5 m that hold no hit, which are decided in sub-blocks of 2^3 voxels and more only.
// Leaves are allocated once per frame, then updated in parallel (TBB); a leaf that ends saturated
// free becomes a tile.
//
// Cost per frame: the image twice (pyramid, hits), one footprint test per block and per voxel of
// the leaves that hold a surface or straddle the frustum's edge, one add per voxel of the free
// leaves that are not yet saturated. Memory: the pyramid (2 x 4/3 x the image) and the hit mask.
#include <openvdb/openvdb.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "mapping/depth_pyramid.h"
#include "mapping/occupancy_map.h"

namespace pensight::mapping {

struct IntegrationStats {
  bool integrated = false;  // false: the pose was not finite, nothing changed
  size_t hit_voxels = 0;
  size_t surface_leaves = 0;    // leaves tested voxel by voxel
  size_t free_leaves = 0;       // stored leaves cleared as a whole
  size_t free_tiles = 0;        // tiles (unknown or free leaves, never stored) cleared
  size_t saturated_leaves = 0;  // free tiles skipped: already saturated
};

class ProjectiveIntegrator {
 public:
  // The camera of the depth images: pinhole without distortion (undistort the depth image first).
  // Throws pensight::Error for a distorted camera or a config out of range.
  ProjectiveIntegrator(const PinholeCamera& camera, const MapConfig& config);

  // Integrates depth_m (z-depth in metres at the camera's resolution; 0, NaN, negative: no
  // measurement) seen from T_pen_camera (camera -> P). A pose with a non-finite entry skips the
  // frame (integrated = false). Throws pensight::Error when the image size is not the camera's or
  // the map's voxel size differs from the integrator's config.
  IntegrationStats integrate(OccupancyMap& map, const ImageF32& depth_m,
                             const Eigen::Isometry3d& T_pen_camera);

 private:
  IntegrationStats integrate_in_arena(OccupancyMap& map, const ImageF32& depth_m,
                                      const Eigen::Isometry3d& T_pen_camera);
  PinholeCamera camera_;
  MapConfig config_;
  tbb::task_arena arena_;  // config.threads workers
  DepthPyramid pyramid_;
};

}  // namespace pensight::mapping
