#pragma once
// wavemap (ETH ASL) as the benchmark's peer integrator: the same depth images and poses, at the
// same resolution.
//
// Version: github ethz-asl/wavemap, main at db4f2fffdc1da1bec042d51bfff58029c0c9c827 (2024-12-10,
// tag v2.2.1), its C++ library (library/cpp) built Release as shared libraries with the Debian 12
// Eigen 3.4, glog 0.6 and Boost 1.74 headers, without tracy. It is built outside the repository
// and found through the cache variable PENSIGHT_WAVEMAP_DIR (bench/mapping/wavemap.cmake).
//
// Settings: wavemap's own setup for depth cameras, as in its
// interfaces/ros1/wavemap_ros/config/wavemap_panoptic_mapping_rgbd.yaml (an RGB-D camera at 2 cm)
// and docs/pages/parameters/measurement_integrators.rst:
//   map:                hashed_chunked_wavelet_octree, min_cell_width = voxel_m, the defaults
//                       otherwise (log-odds clamped to [-2, 4], tree height 6)
//   projection_model:   pinhole_camera_projector from the PinholeCamera (distortion is ignored:
//                       wavemap has no distortion model, the benchmark's images are undistorted)
//   measurement_model:  continuous_ray, range_sigma 0.01 m, scaling_free 0.2,
//                       scaling_occupied 0.4 (the recommended model for dense, short-range sensors)
//   integration_method: hashed_chunked_wavelet_integrator (its fastest), min_range_m, max_range_m
//   thread pool:        2 threads (wavemap's default is one per hardware thread; the product runs
//                       on 2 cores)
//   map operations:     threshold every 20th frame and pruneSmart every 100th frame, i.e. the
//                       config's "once_every 2 s / 10 s" at the sequence's 10 Hz, counted in frames
//                       so the benchmark does not depend on how fast it runs
//
// wavemap compiles with -march=native and Eigen aligned to the widest vector unit, so this adapter
// is a shared library compiled with wavemap's flags that exports only WavemapPeer: no Eigen code
// compiled with those flags can replace the benchmark's own (bench/mapping/wavemap.cmake).
#include <Eigen/Geometry>
#include <cstddef>
#include <memory>

#include "core/camera.h"  // pensight::PinholeCamera {width_px, height_px, fx_px, fy_px, cx_px, cy_px}
#include "core/image.h"  // pensight::ImageF32 {width, height, pixels (row-major float)}

namespace pensight::bench {

struct WavemapPeerConfig {
  double voxel_m = 0.02;
  double min_range_m = 0.1;
  double max_range_m = 5.0;
};

class WavemapPeer {
 public:
  WavemapPeer(const PinholeCamera& camera, WavemapPeerConfig config);
  ~WavemapPeer();
  // depth_m: z-depth in metres per pixel (0 or NaN = no measurement); T_pen_camera: camera -> world
  // (camera frame is OpenCV: x right, y down, z forward).
  void integrate(const ImageF32& depth_m, const Eigen::Isometry3d& T_pen_camera);
  size_t memory_bytes() const;  // the map's memory as wavemap reports it
  // log-odds occupancy at a world point (for a sanity check that the map is right)
  float log_odds_at(const Eigen::Vector3d& p_pen) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight::bench
