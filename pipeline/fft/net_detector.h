#pragma once
// The FFT net detection stage as one object: ROI grid -> per-ROI lattice (CPU/FFTW, Vulkan or
// CUDA) -> per-ROI net points -> sparse depths and the FFT relative pose, with timings. Built once
// per camera and configuration (plans, pipelines, buffers and the recorded command stream are
// made in the constructor); detect() is called per frame.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/backend.h"
#include "core/camera.h"
#include "kernels/fft_roi/fft_roi.h"
#include "pipeline/fft/depth_priors.h"
#include "pipeline/fft/mesh_angle.h"
#include "pipeline/fft/net_geometry.h"
#include "pipeline/fft/net_texture.h"
#include "pipeline/fft/relative_pose_fft.h"
#include "runtime/device.h"

namespace pensight {

struct NetDetectorConfig {
  // 5 x 6 ROIs; roi_size_px 0 and fft_size 0: planned from the camera and the bar length
  // (grid_plan.h; 300 and 256 px on the reference 720x540 camera).
  kernels::RoiGrid grid{.rows = 5, .cols = 6, .roi_size_px = 0, .border_px = 0};
  int fft_size = 0;  // resampled ROI side
  bool window = true;
  kernels::PeakParams peaks;
  NetPointParams points;
  // Correct each ROI's lattice for its perspective chirp on the fitted plane and fit again
  // (lattice_chirp.h); off: the spectral peak is taken as the lattice at the ROI's point.
  bool chirp_correction = true;
  RelativePoseFftParams pose;
  DepthPriorParams priors;      // NetDetection::depths
  NetTextureParams texture;     // NetDetection::texture
  double bar_length_m = 0.030;  // bar length, from scene.yaml net_mesh_size_m
  // scene.yaml's optional net_mesh_type and net_mesh_angle_deg: a prior; estimated when absent.
  std::optional<MeshType> mesh_type;
  std::optional<double> mesh_angle_rad;
  MeshAngleParams mesh_angle;
  MeshAngleFilter::Params mesh_angle_filter;
  // kAuto: CUDA when built with it and a device is present, else a real Vulkan GPU, else the CPU
  // (lavapipe is for tests, never chosen automatically).
  Backend backend = Backend::kAuto;
  int cpu_threads = 0;  // 0: all hardware threads
};

struct NetDetection {
  int64_t timestamp_ns = 0;  // the frame's, passed through
  // The grid this frame was analysed on: the planned one, or native ROIs of the FFT's side where
  // the mesh is finer than the planned ROIs hold (fine_mesh_probe.h).
  std::vector<kernels::RoiOrigin> rois;
  int roi_size_px = 0;
  std::vector<kernels::RoiLattice> lattices;  // per ROI, grid order
  std::vector<RoiNetPoint> points;            // per ROI, grid order
  // Priors for depth completion on the inlier ROIs' local surfaces (depth_priors.h); empty
  // when the pose is NaN.
  std::vector<SparseDepth> depths;
  FftRelativePose pose;
  // The move of the net point at the image centre since the previous frame, in bars
  // (net_texture.h); valid = false on the first frame and where the lattice is not clear.
  TextureStep texture;
  // The net's opening angle (mesh_angle.h) the points were modelled with: smoothed over frames;
  // NaN until a frame has measured it (or the scene gave it).
  double mesh_angle_rad = kNaN;
  MeshType mesh_type = MeshType::kSquare;  // given, else what the frame's lattice shows
  MeshAngleMeasurement mesh_angle_frame;   // this frame's own measurement
  int reduced_rois = 0;                    // ROIs whose spectral basis held a diagonal
  double fft_ms = 0;                       // lattice stage incl. upload/download (wall clock)
  double pose_ms = 0;                      // the fine-mesh probe, net points, relative pose
};

class NetDetector {
 public:
  // The Vulkan backend runs on `device`'s context, which must outlive the detector. Throws
  // pensight::Error when the config is not valid (net_detector_params.h), the grid does not fit
  // the camera image, or an explicitly requested backend is unavailable.
  NetDetector(const PinholeCamera& camera, const NetDetectorConfig& config, Device& device);
  ~NetDetector();
  NetDetector(NetDetector&&) noexcept;
  NetDetector& operator=(NetDetector&&) noexcept;

  Backend backend() const;  // the backend in use (never kAuto)
  // e.g. "cpu (FFTW, 2 threads), 5x6 ROIs of 300 px, FFT 256" or "vulkan (NVIDIA ...), ..."
  std::string description() const;
  const std::vector<kernels::RoiOrigin>& rois() const;
  // The configuration in use: the one given with the grid and FFT size planned (grid_plan.h).
  const NetDetectorConfig& config() const;

  // Throws pensight::Error when the image size differs from the camera's. Frames are taken in
  // time order: the opening angle is smoothed across them.
  NetDetection detect(const ImageU8& image, int64_t timestamp_ns = 0);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight
