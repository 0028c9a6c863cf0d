#pragma once
// The plain per-pixel ray-casting integrator (the method of OctoMap's insertPointCloud): per
// valid pixel, the voxels from the camera centre to the measured point (voxel_ray.h) get a miss,
// the voxel holding the point a hit; a pixel beyond max_range_m clears its ray up to max_range_m
// and adds no hit. Each voxel is updated at most once per frame: the frame's hit and miss voxels
// are collected first, a voxel that is both counts as a hit, then the map is updated.
//
// Serial and simple on purpose: it is the reference that the projective integrator
// (projective_integrator.h) is compared with in bench/mapping_bench.cpp. Cost per frame: one
// voxel step and one set insertion per voxel crossed by every pixel's ray (~depth / voxel per
// pixel), then one update per distinct voxel.
#include <Eigen/Geometry>

#include "core/camera.h"
#include "core/image.h"
#include "mapping/occupancy_map.h"
#include "mapping/projective_integrator.h"

namespace pensight::mapping {

class RaycastIntegrator {
 public:
  // The camera of the depth images: pinhole without distortion. Throws pensight::Error for a
  // distorted camera or a config out of range.
  RaycastIntegrator(const PinholeCamera& camera, const MapConfig& config);

  // As ProjectiveIntegrator::integrate (same inputs, same errors); of the stats only integrated
  // and hit_voxels are filled.
  IntegrationStats integrate(OccupancyMap& map, const ImageF32& depth_m,
                             const Eigen::Isometry3d& T_pen_camera);

 private:
  PinholeCamera camera_;
  MapConfig config_;
};

}  // namespace pensight::mapping
