#pragma once
// `pensight run`: a dataset replayed through pensight::Pipeline (the code a vehicle runs), writing
// OUT/estimates.csv, OUT/diagnostics.csv, OUT/timing.csv, OUT/overlays/, OUT/report.html and, as
// the baseline, the published global-pose node's output OUT/global_pose_published.csv.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/fft/net_detector.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/pipeline.h"
#include "runtime/device.h"
#include "tools/timing_table.h"

namespace pensight {

inline constexpr size_t kReportOverlays = 4;

struct RunOptions {
  // The camera and the mesh size come from the dataset; everything else from here.
  NetDetectorConfig detector;
  // Also run the published global-pose node and write OUT/global_pose_published.csv.
  bool write_published_global_pose = true;
  // Push each sample at its timestamp (relative to the first) instead of as fast as possible, so
  // the timing is a vehicle's at the dataset's rates.
  bool realtime = false;
  // OUT/overlays/<cam0 file>.png for every frame (tools/report/overlay.h); without it, for
  // kReportOverlays evenly spaced frames, which OUT/report.html shows.
  bool overlays = false;
  // Called after each frame with (frames done, total frames), on the pipeline's delivery thread.
  std::function<void(size_t, size_t)> on_progress;
  // Hand each frame the dataset's ground-truth depth (groundtruth0/depth/) in CameraFrame::depth_m,
  // the mapping stage's input until the dense-depth stage produces it. Throws pensight::Error
  // when the dataset has none.
  bool truth_depth = false;
  // The dense-depth stage: OUT/depth/<cam0 file> (contract 1.1) and the *_depth columns of
  // estimates.csv; off when unset.
  std::optional<DepthEstimatorConfig> depth;
  // The dense depth's scale from the DVL's beam ranges (PipelineConfig::dvl_depth_scale).
  bool dvl_depth_scale = true;
  // The dense depth's tilt from the DVL's beam ranges (PipelineConfig::dvl_net_tilt).
  bool dvl_net_tilt = true;
  // Stages outside the pipeline layer (the mapping stage) that take every result.
  struct AttachedStage {
    // On the delivery thread, after the frame's rows are written; must not block.
    std::function<void(const FrameResult&)> push;
    // After the last frame: drains the stage, writes its outputs, returns its timing row.
    std::function<StageStats()> finish;
  };
  std::vector<AttachedStage> stages;
  // What the user ran on, when not the dataset folder (a bag converted for the run): the report
  // names it.
  std::filesystem::path input;
};

struct RunSummary {
  std::string backend;        // e.g. "cpu (FFTW, 2 threads)"
  std::string depth_backend;  // e.g. "opencv dnn (2 threads), 320x240, 1.20 GFLOP"; empty when off
  size_t frames_with_depth = 0;
  size_t frames = 0;
  size_t frames_skipped = 0;  // unreadable or wrong-size images: NaN rows, with a warning each
  size_t frames_without_pose = 0;
  std::vector<TimingRow> timing;     // as OUT/timing.csv
  std::string global_pose_counters;  // per-sensor accepted / rejected / late counts
};

// `base` with what scene.yaml says of the net: its bar, and the mesh type and opening angle where
// given (the detector estimates what is absent).
NetDetectorConfig detector_config(const SceneConfig& scene, NetDetectorConfig base = {});

// The estimators' settings from the dataset: pen radius, camera mount, DVL beams, which sensors
// are present.
global_pose::GlobalPoseEstimatorConfig global_pose_config(const Dataset& dataset);
// The same from the parts (a closed loop, which has no dataset to read).
global_pose::GlobalPoseEstimatorConfig global_pose_config(const SceneConfig& scene,
                                                          const CameraCalibration& cam0,
                                                          const std::optional<DvlCalibration>& dvl0,
                                                          bool has_pressure, bool has_attitude);

// Writes the outputs whole (temporary name, then rename), creating out_dir if needed. Runs the
// detector's Vulkan backend on `device`.
// Throws pensight::Error for problems that affect the whole run (unwritable output, a backend
// that cannot run here, a ROI grid that does not fit the camera).
RunSummary run_dataset(const Dataset& dataset, const std::filesystem::path& out_dir,
                       const RunOptions& options, Device& device);

}  // namespace pensight
