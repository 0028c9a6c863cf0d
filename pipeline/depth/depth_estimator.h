#pragma once
// The dense-depth stage: a frame's image and the FFT detector's sparse priors -> a depth-completion
// network (image + S1 + S2 (+ the prior surface Q) -> metric z-depth, TRUDepth's input form) ->
// depth at the camera's resolution and the net-relative pose from it (depth_plane.h). The
// network's output is multiplied by a surface through the ratios prior / network at the priors'
// pixels before it is resized (align_to_priors, prior_surface.h): the priors fix the metric scale
// and the slow shape, the network the detail between them. Built once per camera and model
// (the network is loaded, planned and, on Vulkan, recorded in the constructor); estimate() is
// called per frame.
//
// Model contract (models/README.md): inputs "image" [1,1,H,W] (grey / 255) and "prior" [1,2,H,W]
// (S1 in metres, S2; sparse_prior.h) or [1,3,H,W] (S1, S2 and the prior surface Q in metres,
// prior_surface.h; the shipped model's form), output "depth" [1,1,H,W] in metres. H x W is the
// model's; the image is area-resized to it and the priors moved into its pixels (depth_input.h).
//
// Backends (core/backend.h): the CPU, or the engine's Vulkan executor with S1/S2 computed on the
// device straight into the network's input (Q, a 6-coefficient surface, is rendered on the CPU
// and uploaded beside them); kAuto is Vulkan on a real GPU, else the CPU. On the CPU the network
// runs in OpenCV DNN (Debian's, the fastest correct CPU path, measured in docs/dense_depth.md) or
// in the engine's CPU reference executor; CpuInference::kAuto takes OpenCV DNN where it reads the
// model.
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/backend.h"
#include "core/camera.h"
#include "core/image.h"
#include "pipeline/depth/depth_plane.h"
#include "pipeline/fft/net_geometry.h"
#include "runtime/device.h"

namespace pensight {

// Which library runs the network on the CPU backend.
enum class CpuInference { kAuto, kOpenCv, kEngine };
const char* to_string(CpuInference inference);  // "auto" | "opencv" | "engine"
// Throws pensight::Error listing the choices for any other name.
CpuInference parse_cpu_inference(const std::string& name);

struct DepthEstimatorConfig {
  std::filesystem::path model;       // ONNX file
  Backend backend = Backend::kAuto;  // no CUDA path: kCuda is refused
  CpuInference cpu_inference = CpuInference::kAuto;
  int cpu_threads = 0;  // 0: all hardware threads
  float sigma_px = 10;  // S2's radius in network pixels, as in training
  // The net wall's curvature for the prior surface Q (net_curvature_per_m(SceneConfig); 0: flat),
  // as the training data gives it (sim/depth_training.h).
  double net_curvature_per_m = 0;
  DepthPlaneParams plane;
};

// Throws pensight::Error "depth: key 'PATH': VALUE is outside RANGE UNIT (HELP)" for the first
// numeric value out of its range, the plane's under "plane.".
void validate(const DepthEstimatorConfig& config);
// Every numeric key of the dense-depth stage with its default, unit, valid range and help: the
// rows of a Markdown table under core/params.h's kParamTableHeader. DepthEstimatorConfig's keys,
// its plane's under "plane.", and DvlDepthScaleConfig's and DvlNetTiltConfig's under
// "dvl_depth_scale." and "dvl_net_tilt." (PipelineConfig's names).
std::string depth_param_rows();

struct DenseDepth {
  // Camera resolution; empty when `reason` is set. NaN outside the network's view (a camera of
  // another aspect than the network's: network_view() in depth_input.h).
  ImageF32 depth_m;
  DepthPlanePose pose;
  std::string reason;     // why this frame has no dense depth (no priors); empty when it has
  double network_ms = 0;  // priors + network + resize (wall clock)
  double pose_ms = 0;
};

class DepthEstimator {
 public:
  // Throws pensight::Error naming the file: missing or unreadable model, or one that is not a
  // depth network (inputs/outputs other than the contract's); an explicitly requested backend
  // or CPU inference that is not available; and like validate(config).
  DepthEstimator(const PinholeCamera& camera, const DepthEstimatorConfig& config, Device& device);
  ~DepthEstimator();
  DepthEstimator(DepthEstimator&&) noexcept;
  DepthEstimator& operator=(DepthEstimator&&) noexcept;

  Backend backend() const;             // kCpu or kVulkan
  CpuInference cpu_inference() const;  // on kCpu: kOpenCv or kEngine
  std::string description() const;     // e.g. "opencv dnn (2 threads), 320x240, 1.1 GFLOP"
  double gflop() const;                // the network's multiply-adds x 2 per frame

  // Throws pensight::Error when the image size differs from the camera's. No priors: no depth,
  // with the reason.
  DenseDepth estimate(const ImageU8& image, std::span<const SparseDepth> priors);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight
