#include "tools/runner.h"

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/png_io.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "core/timing.h"
#include "core/units.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "pipeline/dataset/trajectory_tum.h"
#include "pipeline/pipeline.h"
#include "tools/report/overlay.h"
#include "tools/report/report_html.h"

namespace pensight {
namespace {

// The published node as the paper ran it: roll = pitch = 0, the latest sample of each sensor.
global_pose::PublishedGlobalPoseConfig published_config(const Dataset& d) {
  global_pose::PublishedGlobalPoseConfig c;
  c.pen_radius_m = d.scene.pen_radius_m;
  c.initial_rho_rad = d.scene.initial_rho_rad.value_or(0.0);
  c.T_body_camera = d.cam0.T_body_camera;
  c.has_dvl = d.dvl0.has_value();
  return c;
}

void fill_global_pose(EstimateRow& row, const global_pose::GlobalPose& g) {
  row.r_g_m = g.r_g_m;
  row.rho_g_rad = g.rho_g_rad;
  row.z_g_m = g.z_g_m;
  row.psi_g_rad = g.psi_g_rad;
}

// Pushes every sensor sample up to t_ns, in timestamp order across the sensors (as a vehicle's
// drivers would have pushed them by the time the frame arrives), optionally waiting for each
// one's time first.
class SensorReplay {
 public:
  SensorReplay(const Dataset& d, Pipeline& p, std::function<void(int64_t)> wait)
      : d_(d), p_(p), wait_(std::move(wait)) {}

  void until(int64_t t_ns) {
    while (true) {
      int64_t next = t_ns;
      int which = -1;
      consider(dvl(), dvl_, 0, next, which);
      consider(depth(), depth_, 1, next, which);
      consider(attitude(), att_, 2, next, which);
      if (which < 0) return;
      wait_(next);
      if (which == 0) p_.push(dvl()[dvl_++]);
      if (which == 1) p_.push(depth()[depth_++]);
      if (which == 2) p_.push(attitude()[att_++]);
    }
  }

 private:
  std::span<const DvlSample> dvl() const {
    return d_.dvl0 ? std::span<const DvlSample>(d_.dvl0->samples) : std::span<const DvlSample>();
  }
  std::span<const PressureSample> depth() const {
    return d_.pressure0 ? std::span<const PressureSample>(*d_.pressure0)
                        : std::span<const PressureSample>();
  }
  std::span<const AttitudeSample> attitude() const {
    return d_.imu0 ? std::span<const AttitudeSample>(*d_.imu0) : std::span<const AttitudeSample>();
  }
  // The earliest sample not yet pushed with a timestamp <= next wins (ties to the lower index).
  template <class Sample>
  static void consider(std::span<const Sample> s, size_t i, int index, int64_t& next, int& which) {
    if (i < s.size() && s[i].timestamp_ns <= next && (which < 0 || s[i].timestamp_ns < next)) {
      next = s[i].timestamp_ns;
      which = index;
    }
  }

  const Dataset& d_;
  Pipeline& p_;
  std::function<void(int64_t)> wait_;
  size_t dvl_ = 0, depth_ = 0, att_ = 0;
};

// The per-frame outputs, written in frame order as results arrive; frames the replay could not
// load get NaN rows in their place (and no trajectory line). The rows are also kept (a few hundred
// bytes a frame) for OUT/report.html, which is built from them rather than from the files.
class RunWriter {
 public:
  RunWriter(const Dataset& d, const std::filesystem::path& out, bool published, RunSummary& s)
      : d_(d),
        summary_(s),
        estimates_(out / "estimates.csv"),
        diagnostics_(out / kDiagnosticsFile),
        trajectory_(out / kTrajectoryTumFile) {
    if (published) published_.emplace(out / kPublishedGlobalPoseFile);
    skipped_.assign(d.frames.size(), "");
  }

  // Overlays of frames 0, every_nth, 2 every_nth, ... into `dir`.
  void overlays(std::filesystem::path dir, size_t every_nth) {
    std::filesystem::create_directories(dir);
    overlay_dir_ = std::move(dir);
    overlay_every_ = std::max<size_t>(every_nth, 1);
  }

  // OUT/depth/ for the dense-depth stage's PNGs.
  void depth_pngs(std::filesystem::path dir) {
    std::filesystem::create_directories(dir);
    depth_dir_ = std::move(dir);
  }

  // Frame i could not be loaded, for `reason` (its diagnostics row says so).
  void skip(size_t i, const std::string& reason) {
    std::lock_guard lock(mutex_);
    skipped_[i] = reason;
    ++summary_.frames_skipped;
  }

  // One result, on the delivery thread.
  void write(const FrameResult& r) {
    std::lock_guard lock(mutex_);
    write_skipped();
    EstimateRow row, published_row;
    row.timestamp_ns = published_row.timestamp_ns = r.timestamp_ns;
    DiagnosticsRow diag;
    diag.timestamp_ns = r.timestamp_ns;
    if (!r.error.empty()) {
      log_warning("frame " + std::to_string(next_) + " skipped (NaN row): " + r.error);
      ++summary_.frames_skipped;
      diag.fft_reason = r.error;
    } else {
      const FftRelativePose& pose = r.detection.pose;
      row.valid_rois = diag.valid_rois = pose.valid_rois;
      diag.inlier_rois = pose.inlier_rois;
      diag.plane_rms_m = pose.rms_residual_m;
      diag.fft_quality = pose.quality;
      diag.fft_reason = pose.reason;
      diag.mesh_angle_deg = rad_to_deg(r.detection.mesh_angle_rad);
      diag.mesh_type = to_string(r.detection.mesh_type);
      diag.reduced_rois = r.detection.reduced_rois;
      if (pose.valid()) {
        row.d_net_fft_m = pose.d_net_m;
        row.psi_net_fft_rad = pose.psi_net_rad;
        row.pitch_net_fft_rad = pose.pitch_net_rad;
      } else {
        ++summary_.frames_without_pose;
      }
      fill_global_pose(row, r.global_pose);
      trajectory_.write(r.timestamp_ns, r.global_pose.T_pen_body);
      if (r.published) fill_global_pose(published_row, *r.published);
      diag.dvl_plane_d_m = r.dvl_plane.d_net_m;
      diag.dvl_plane_psi_rad = r.dvl_plane.psi_net_rad;
      if (r.depth_pose.valid()) {
        row.d_net_depth_m = r.depth_pose.d_net_m;
        row.psi_net_depth_rad = r.depth_pose.psi_net_rad;
        row.pitch_net_depth_rad = r.depth_pose.pitch_net_rad;
      }
      if (r.dense_depth_m) {
        diag.depth_scale = r.depth_scale.scale;
        diag.dvl_depth_ratio = 1 + r.depth_scale.median_rel;
        diag.depth_psi_offset_rad = r.depth_tilt.psi_offset_rad;
        diag.depth_pitch_offset_rad = r.depth_tilt.pitch_offset_rad;
        diag.dvl_depth_psi_diff_rad = r.depth_tilt.psi_diff_rad;
        diag.dvl_depth_pitch_diff_rad = r.depth_tilt.pitch_diff_rad;
      }
      if (r.dense_depth_m && !depth_dir_.empty()) {
        write_png(depth_dir_ / d_.frames[next_].filename, depth_mm_from_m(*r.dense_depth_m));
        ++summary_.frames_with_depth;
      }
      if (!overlay_dir_.empty() && next_ % overlay_every_ == 0 && r.image) {
        const std::filesystem::path name =
            std::filesystem::path(d_.frames[next_].filename).stem().string() + ".png";
        write_overlay_png(overlay_dir_ / name, *r.image, r.detection);
      }
    }
    count_outcomes(r.counters, diag);
    write_rows(row, published_row, diag);
  }

  // After the last result: NaN rows for trailing unreadable frames, then the files are renamed.
  void finish() {
    std::lock_guard lock(mutex_);
    write_skipped();
    estimates_.finish();
    diagnostics_.finish();
    trajectory_.finish();
    if (published_) published_->finish();
  }

  size_t frames_done() const {
    std::lock_guard lock(mutex_);
    return next_;
  }

  // After finish(): the rows written, moved into the report's input.
  void move_rows_into(ReportInput& report) {
    std::lock_guard lock(mutex_);
    report.estimates = std::move(estimate_rows_);
    if (published_) report.published = std::move(published_rows_);
    report.diagnostics = std::move(diagnostics_rows_);
  }

 private:
  void write_skipped() {
    while (next_ < skipped_.size() && !skipped_[next_].empty()) {
      EstimateRow row;
      row.timestamp_ns = d_.frames[next_].timestamp_ns;
      DiagnosticsRow diag;
      diag.timestamp_ns = row.timestamp_ns;
      diag.fft_reason = skipped_[next_];
      write_rows(row, row, diag);
    }
  }

  void write_rows(const EstimateRow& row, const EstimateRow& published_row,
                  const DiagnosticsRow& diag) {
    estimates_.write(row);
    diagnostics_.write(diag);
    estimate_rows_.push_back(row);
    diagnostics_rows_.push_back(diag);
    if (published_) {
      published_->write(published_row);
      published_rows_.push_back(published_row);
    }
    ++next_;
    ++summary_.frames;
  }

  // The samples each sensor had applied and refused since the previous frame.
  void count_outcomes(const global_pose::GlobalPoseCounters& c, DiagnosticsRow& diag) {
    const global_pose::SensorCounters* now[] = {&c.dvl_velocity, &c.dvl_plane,  &c.depth,
                                                &c.attitude,     &c.vision_fix, &c.vision_relative,
                                                &c.net_texture};
    const global_pose::SensorCounters* before[] = {
        &last_.dvl_velocity, &last_.dvl_plane,       &last_.depth,      &last_.attitude,
        &last_.vision_fix,   &last_.vision_relative, &last_.net_texture};
    static_assert(std::size(now) == kDiagnosticsSensors.size());
    for (size_t i = 0; i < kDiagnosticsSensors.size(); ++i) {
      diag.accepted[i] =
          (now[i]->accepted + now[i]->relocked) - (before[i]->accepted + before[i]->relocked);
      diag.rejected[i] =
          (now[i]->rejected + now[i]->invalid) - (before[i]->rejected + before[i]->invalid);
    }
    last_ = c;
  }

  const Dataset& d_;
  RunSummary& summary_;
  mutable std::mutex mutex_;
  EstimatesCsvWriter estimates_;
  DiagnosticsCsvWriter diagnostics_;
  TrajectoryTumWriter trajectory_;  // frames with a body pose only
  std::optional<GlobalPoseCsvWriter> published_;
  std::vector<EstimateRow> estimate_rows_, published_rows_;
  std::vector<DiagnosticsRow> diagnostics_rows_;
  std::vector<std::string> skipped_;   // per frame: why it could not be loaded, or empty
  std::filesystem::path overlay_dir_;  // empty: no overlays
  size_t overlay_every_ = 1;
  std::filesystem::path depth_dir_;
  size_t next_ = 0;  // frames with a row
  global_pose::GlobalPoseCounters last_;
};

}  // namespace

NetDetectorConfig detector_config(const SceneConfig& scene, NetDetectorConfig base) {
  base.bar_length_m = scene.bar_length_m;
  base.mesh_type = scene.net_mesh_type;
  base.mesh_angle_rad = scene.net_mesh_angle_rad;
  base.pose.wall_curvature_per_m = net_curvature_per_m(scene);
  return base;
}

global_pose::GlobalPoseEstimatorConfig global_pose_config(const SceneConfig& scene,
                                                          const CameraCalibration& cam0,
                                                          const std::optional<DvlCalibration>& dvl0,
                                                          bool has_pressure, bool has_attitude) {
  global_pose::GlobalPoseEstimatorConfig c;
  c.pen_radius_m = scene.pen_radius_m;
  c.flat_panel = scene.flat_panel;
  c.initial_rho_rad = scene.initial_rho_rad.value_or(0.0);
  c.T_body_camera = cam0.T_body_camera;
  if (dvl0) c.dvl_beams = *dvl0;
  c.has_dvl = dvl0.has_value();
  c.has_attitude = has_attitude;
  c.has_pressure = has_pressure;
  return c;
}

global_pose::GlobalPoseEstimatorConfig global_pose_config(const Dataset& d) {
  std::optional<DvlCalibration> dvl;
  if (d.dvl0) dvl = d.dvl0->calibration;
  return global_pose_config(d.scene, d.cam0, dvl, d.pressure0.has_value(), d.imu0.has_value());
}

RunSummary run_dataset(const Dataset& dataset, const std::filesystem::path& out_dir,
                       const RunOptions& options, Device& device) {
  RunSummary summary;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create output folder " + out_dir.string() + ": " + ec.message());
  if (options.truth_depth && !(dataset.groundtruth0 && dataset.groundtruth0->has_depth)) {
    throw Error("'" + dataset.root.string() +
                "' has no groundtruth0/depth/ to map with; map a rendered dataset, or run without "
                "the ground-truth depth");
  }
  RunWriter writer(dataset, out_dir, options.write_published_global_pose, summary);

  const size_t total = dataset.frames.size();
  PipelineConfig config;
  config.camera = dataset.cam0.camera;
  config.detector = detector_config(dataset.scene, options.detector);
  config.global_pose = global_pose_config(dataset);
  if (options.write_published_global_pose) config.published = published_config(dataset);
  config.depth = options.depth;
  if (config.depth) config.depth->net_curvature_per_m = net_curvature_per_m(dataset.scene);
  if (!options.dvl_depth_scale) config.dvl_depth_scale.reset();
  if (!options.dvl_net_tilt) config.dvl_net_tilt.reset();
  config.lossless_results = true;
  // A failed write (disk full) ends the run after the pipeline drains, with no output renamed.
  std::exception_ptr write_error;
  config.on_frame = [&](const FrameResult& r) {
    if (write_error) return;
    try {
      writer.write(r);
    } catch (...) {
      write_error = std::current_exception();
      return;
    }
    for (const RunOptions::AttachedStage& stage : options.stages) stage.push(r);
    if (options.on_progress) options.on_progress(writer.frames_done(), total);
  };
  Pipeline pipeline(config, device);
  summary.backend = pipeline.backend_description();
  summary.depth_backend = pipeline.depth_description();
  if (options.depth) writer.depth_pngs(out_dir / "depth");
  writer.overlays(out_dir / "overlays",
                  options.overlays ? 1 : (total + kReportOverlays - 1) / kReportOverlays);

  const auto start = std::chrono::steady_clock::now();
  const int64_t t0 = total ? dataset.frames.front().timestamp_ns : 0;
  const auto wait = [&](int64_t t_ns) {
    if (options.realtime)
      std::this_thread::sleep_until(start + std::chrono::nanoseconds(t_ns - t0));
  };
  SensorReplay sensors(dataset, pipeline, wait);
  StageMeter load("load image");
  for (size_t i = 0; i < total; ++i) {
    const int64_t t_ns = dataset.frames[i].timestamp_ns;
    sensors.until(t_ns);
    Stopwatch sw;
    const auto began = StageMeter::Clock::now();
    CameraFrame frame{t_ns, {}};
    try {
      frame.image = dataset.load_frame(i);
      if (options.truth_depth) {
        frame.depth_m = std::make_shared<const ImageF32>(dataset.load_depth_m(i));
      }
    } catch (const Error& e) {
      log_warning("frame " + std::to_string(i) + " skipped (NaN row): " + e.what());
      writer.skip(i, e.what());
      continue;
    }
    load.add(sw.elapsed_ms(), began);
    wait(t_ns);
    pipeline.push(std::move(frame));
  }
  sensors.until(std::numeric_limits<int64_t>::max());
  pipeline.finish();
  if (write_error) std::rethrow_exception(write_error);
  writer.finish();

  std::vector<StageStats> stages = pipeline.stats();
  stages.insert(stages.begin(), load.stats());
  for (const RunOptions::AttachedStage& stage : options.stages) stages.push_back(stage.finish());
  summary.timing = timing_table(stages);
  summary.global_pose_counters = global_pose::describe(pipeline.global_pose_counters());
  write_timing_csv(out_dir / kTimingFile, summary.timing);
  ReportInput report{.out_dir = out_dir, .dataset = &dataset, .input = options.input};
  writer.move_rows_into(report);
  report.timing = summary.timing;
  write_report_html(report);
  return summary;
}

}  // namespace pensight
