#include "bench/mapping/wavemap_peer.h"

#include <wavemap/core/common.h>
#include <wavemap/core/data_structure/image.h>
#include <wavemap/core/integrator/measurement_model/continuous_ray.h>
#include <wavemap/core/integrator/projection_model/pinhole_camera_projector.h>
#include <wavemap/core/integrator/projective/coarse_to_fine/hashed_chunked_wavelet_integrator.h>
#include <wavemap/core/map/hashed_chunked_wavelet_octree.h>
#include <wavemap/core/utils/query/map_interpolator.h>
#include <wavemap/core/utils/thread_pool.h>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

namespace pensight::bench {

namespace {

// wavemap_panoptic_mapping_rgbd.yaml's continuous_ray model (see the header).
constexpr float kRangeSigma_m = 0.01f;
constexpr float kScalingFree = 0.2f;
constexpr float kScalingOccupied = 0.4f;
// Its map operations "threshold once every 2 s" and "prune once every 10 s" at 10 Hz.
constexpr int kThresholdEveryFrames = 20;
constexpr int kPruneEveryFrames = 100;
constexpr size_t kThreads = 2;

// The caller's Isometry3d is aligned for the benchmark's flags, not for this file's wider vector
// unit, so its matrix is read through an unaligned map.
wavemap::Transformation3D to_wavemap(const Eigen::Isometry3d& T_pen_camera) {
  const Eigen::Map<const Eigen::Matrix4d, Eigen::Unaligned> T(T_pen_camera.matrix().data());
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::Quaternionf q = Eigen::Quaterniond(R).normalized().cast<float>().normalized();
  const wavemap::Point3D t = T.topRightCorner<3, 1>().cast<float>();
  return wavemap::Transformation3D(wavemap::Rotation3D(q), t);
}

}  // namespace

struct WavemapPeer::Impl {
  std::shared_ptr<wavemap::HashedChunkedWaveletOctree> map;
  std::unique_ptr<wavemap::HashedChunkedWaveletIntegrator> integrator;
  // wavemap's images are column-major with rows = image x, the same memory order as ImageF32.
  wavemap::PosedImage<> depth;
  int frames = 0;
};

WavemapPeer::WavemapPeer(const PinholeCamera& camera, WavemapPeerConfig config) {
  wavemap::HashedChunkedWaveletOctreeConfig map_config;
  map_config.min_cell_width = static_cast<float>(config.voxel_m);
  auto map = std::make_shared<wavemap::HashedChunkedWaveletOctree>(map_config);

  const wavemap::PinholeCameraProjectorConfig projector_config(
      static_cast<float>(camera.fx_px), static_cast<float>(camera.fy_px),
      static_cast<float>(camera.cx_px), static_cast<float>(camera.cy_px), camera.height_px,
      camera.width_px);
  auto projector = std::make_shared<wavemap::PinholeCameraProjector>(projector_config);
  // The integrator and the measurement model share these images, as in wavemap's
  // IntegratorFactory.
  auto range_image = std::make_shared<wavemap::PosedImage<>>(projector->getDimensions());
  auto beam_offset_image =
      std::make_shared<wavemap::Image<wavemap::Vector2D>>(projector->getDimensions());
  auto measurement_model = std::make_shared<wavemap::ContinuousRay>(
      wavemap::ContinuousRayConfig(kRangeSigma_m, kScalingFree, kScalingOccupied), projector,
      range_image);
  const wavemap::ProjectiveIntegratorConfig integrator_config(
      static_cast<float>(config.min_range_m), static_cast<float>(config.max_range_m));
  auto integrator = std::make_unique<wavemap::HashedChunkedWaveletIntegrator>(
      integrator_config, std::move(projector), std::move(range_image), std::move(beam_offset_image),
      std::move(measurement_model), map, std::make_shared<wavemap::ThreadPool>(kThreads));

  impl_ = std::make_unique<Impl>(Impl{
      .map = std::move(map),
      .integrator = std::move(integrator),
      .depth = wavemap::PosedImage<>(camera.width_px, camera.height_px),
  });
}

WavemapPeer::~WavemapPeer() = default;

void WavemapPeer::integrate(const ImageF32& depth_m, const Eigen::Isometry3d& T_pen_camera) {
  if (depth_m.width != impl_->depth.getNumRows() ||
      depth_m.height != impl_->depth.getNumColumns()) {
    throw std::invalid_argument("WavemapPeer::integrate: the depth image is not the camera's size");
  }
  // wavemap's hierarchical range image compares depths with < and >, which NaN would poison; 0 is
  // below min_range, i.e. no measurement, as for the benchmark's own integrator.
  float* dst = impl_->depth.getData().data();
  for (const float d : depth_m.pixels) *dst++ = std::isnan(d) ? 0.0f : d;
  impl_->depth.setPose(to_wavemap(T_pen_camera));
  impl_->integrator->integrate(impl_->depth);

  ++impl_->frames;
  if (impl_->frames % kThresholdEveryFrames == 0) impl_->map->threshold();
  if (impl_->frames % kPruneEveryFrames == 0) impl_->map->pruneSmart();
}

size_t WavemapPeer::memory_bytes() const {
  return impl_->map->getMemoryUsage();
}

float WavemapPeer::log_odds_at(const Eigen::Vector3d& p_pen) const {
  return wavemap::interpolate::nearestNeighbor(*impl_->map, p_pen.cast<float>().eval());
}

}  // namespace pensight::bench
