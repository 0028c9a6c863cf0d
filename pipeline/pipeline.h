#pragma once
// pensight::Pipeline, the embedding API: a vehicle program (or `pensight run`, which replays a
// dataset through it) pushes camera frames and DVL, pressure and attitude samples from any
// thread, and receives one FrameResult per camera frame, in frame order.
//
// A frame's whole path:
//   push(CameraFrame) -> [camera queue, blocking] -> detection worker: NetDetector::detect
//     (FFT lattice per ROI, net points, FFT relative pose)
//   -> [depth queue, blocking; when PipelineConfig::depth is set] -> dense-depth worker:
//     DepthEstimator::estimate (priors -> network -> depth image, pose from dense depth)
//   -> [pose queue, blocking] -> global-pose worker: feeds the estimators every sensor sample up
//     to the frame's timestamp (samples pushed before the frame, or late ones), adds the frame's
//     net observation, asks for the estimate at the frame's time
//   -> [result queue] -> on_frame callback (its own thread) or poll().
// Sensor samples go straight to the global-pose worker, which holds those newer than the frame it
// is working on, so the estimators see nothing from the future whatever the threads' timing: the
// results are those of calling the stages one after another (run_dataset relies on it). Samples
// that arrive after their frame are late for it (PipelineConfig::sensor_wait_ms bounds how long
// the worker waits for them).
//
// The pose path never drops: a full camera queue makes push() wait. The result queue drops its
// oldest result (counted in stats()) when the caller falls behind, unless lossless_results is set.
// Timestamps are nanoseconds on one clock for every sensor.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset_types.h"
#include "core/image.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/dvl_depth_correction.h"
#include "pipeline/fft/net_detector.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "pipeline/stage_stats.h"
#include "runtime/device.h"

namespace pensight {

struct CameraFrame {
  int64_t timestamp_ns = 0;
  ImageU8 image;  // the camera's resolution, 8-bit grey
  // Optional z-depth in metres registered to the image (a depth sensor's, or replayed ground
  // truth), handed on in FrameResult for the mapping stage (mapping/mapping_stage.h).
  std::shared_ptr<const ImageF32> depth_m;
};

struct FrameResult {
  int64_t timestamp_ns = 0;
  std::shared_ptr<const ImageU8> image;  // the frame as pushed (for overlays), shared, not copied
  std::shared_ptr<const ImageF32> depth_m;  // CameraFrame::depth_m, shared, not copied
  // Why the frame was not processed (e.g. wrong image size) or its global pose failed; when set,
  // the estimates below are empty or NaN.
  std::string error;
  NetDetection detection;
  global_pose::GlobalPose global_pose;
  std::optional<global_pose::GlobalPose> published;  // when PipelineConfig::published is set
  // The dense-depth stage's z-depth in metres at the camera's resolution; null when the stage is
  // off or the frame had none (depth_pose.reason says why).
  std::shared_ptr<const ImageF32> dense_depth_m;
  DepthPlanePose depth_pose;  // the net-relative pose from dense_depth_m
  // The DVL's measure of the net's bar length; when engaged, dense_depth_m and depth_pose.d_net_m
  // are already multiplied by its scale.
  DvlDepthScaleState depth_scale;
  // The DVL's measure of the net's tilt; when engaged, dense_depth_m is turned and
  // depth_pose.psi_net_rad / pitch_net_rad carry its offsets.
  DvlNetTiltState depth_tilt;
  double depth_ms = 0;  // priors + network + resize
  // The latest DVL net plane as the camera's net-relative pose, when at most 0.5 s old (NaN else).
  global_pose::NetRelativePose dvl_plane;
  // The estimator's counters after this frame (cumulative since the start).
  global_pose::GlobalPoseCounters counters;
  double global_pose_ms = 0;  // this frame's work in the global-pose worker
};

struct PipelineConfig {
  PinholeCamera camera;
  NetDetectorConfig detector;  // its bar_length_m is the net's (scene.yaml net_mesh_size_m)
  global_pose::GlobalPoseEstimatorConfig global_pose;
  // The dense-depth stage (a model file, its backend and the net wall's curvature,
  // net_curvature_per_m(scene)); off when unset.
  std::optional<DepthEstimatorConfig> depth;
  // The dense depth's scale from the DVL's beam ranges (dvl_depth_scale.h): with the depth stage
  // and global_pose.dvl_beams; off when unset.
  std::optional<DvlDepthScaleConfig> dvl_depth_scale = DvlDepthScaleConfig{};
  // The dense depth's tilt from the DVL's beam ranges (dvl_net_tilt.h), applied before the scale;
  // with the depth stage and global_pose.dvl_beams; off when unset.
  std::optional<DvlNetTiltConfig> dvl_net_tilt = DvlNetTiltConfig{};
  // Also run the published global-pose node (the baseline) on the same inputs.
  std::optional<global_pose::PublishedGlobalPoseConfig> published;
  // Called on the pipeline's delivery thread for each result, in frame order (an exception it
  // throws is logged and delivery goes on). Without it, results wait for poll().
  std::function<void(const FrameResult&)> on_frame;
  size_t camera_queue = 4;   // frames waiting for detection; push(CameraFrame) waits beyond
  size_t result_queue = 64;  // results waiting for the caller
  // Replay: make the result queue wait for the caller instead of dropping its oldest result.
  bool lossless_results = false;
  // Live transports (ROS topics) can deliver a sensor sample just after the frame it precedes.
  // With this > 0 the global-pose worker, before a frame, waits up to this long (counted from the
  // frame's push) for each sensor whose next sample is due by the frame's time (from the
  // sensor's own rate), so the frame's estimate uses the samples a replay would give it. A sensor
  // that stopped costs this wait per frame, nothing more. 0: no wait (replay pushes in order).
  double sensor_wait_ms = 0;
};

// The global-pose stage's input from one frame's detection: every ROI's net point (NaN where the
// ROI has none) with its quality, and the FFT d_net / psi_net when the pose is valid.
global_pose::NetObservation net_observation(const NetDetection& detection);

class Pipeline {
 public:
  // Builds the stages (plans, pipelines and buffers on `device`, which must outlive the pipeline)
  // and starts the workers. Throws pensight::Error like NetDetector for a bad configuration.
  Pipeline(PipelineConfig config, Device& device);
  // finish(), then joins the workers.
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Thread-safe. Throws pensight::Error after finish(), and DeviceLostError once the device was
  // lost (the run cannot go on; a new Pipeline on a new Device, or the CPU backend, can).
  void push(CameraFrame frame);
  void push(const DvlSample& s);
  void push(const PressureSample& s);
  void push(const AttitudeSample& s);

  // The oldest undelivered result, if any (only without on_frame).
  std::optional<FrameResult> poll();

  // Stops taking input, processes everything already pushed (every frame gets its result; the
  // sensor samples held after the last frame are given to the estimators) and delivers it; on
  // return every on_frame call has finished. Idempotent. Throws DeviceLostError when the device
  // was lost: the frames from the lost one on have no results.
  void finish();

  // Per stage: "fft net detection", "relative pose (fft)", with the dense-depth stage "dense
  // depth" and "relative pose (depth)", then "global pose", "delivery"; latency
  // from push() of the frame. Safe to call while running.
  std::vector<StageStats> stats() const;
  std::string backend_description() const;
  // The dense-depth stage's backend, network size and GFLOP; empty when the stage is off.
  std::string depth_description() const;
  // The global-pose estimator's counters once finish() returned; throws pensight::Error before.
  global_pose::GlobalPoseCounters global_pose_counters() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight
