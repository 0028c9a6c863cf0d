#include "pipeline/runner.h"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "runtime/error.h"
#include "runtime/log.h"

namespace pensight {
namespace {

global_pose::GlobalPoseEstimatorConfig global_pose_config(const Dataset& d) {
  global_pose::GlobalPoseEstimatorConfig c;
  c.pen_radius_m = d.scene.pen_radius_m;
  c.initial_rho_rad = d.scene.initial_rho_rad.value_or(0.0);
  c.T_body_camera = d.cam0.T_BS;
  if (d.dvl0) c.dvl_beams = d.dvl0->calibration;
  c.has_dvl = d.dvl0.has_value();
  c.has_attitude = d.imu0.has_value();
  c.has_pressure = d.pressure0.has_value();
  return c;
}

// The published node as the paper ran it: roll = pitch = 0, the latest sample of each sensor.
global_pose::PublishedGlobalPoseConfig published_config(const Dataset& d) {
  global_pose::PublishedGlobalPoseConfig c;
  c.pen_radius_m = d.scene.pen_radius_m;
  c.initial_rho_rad = d.scene.initial_rho_rad.value_or(0.0);
  c.T_body_camera = d.cam0.T_BS;
  c.has_dvl = d.dvl0.has_value();
  return c;
}

// Feeds the estimators every DVL, pressure and attitude sample up to each camera frame's time,
// so they see the sensors as a vehicle would (nothing from the future).
class SensorFeed {
 public:
  explicit SensorFeed(const Dataset& d) : d_(d) {}

  void until(int64_t t_ns, global_pose::GlobalPoseEstimator& est,
             global_pose::PublishedGlobalPose* published) {
    if (d_.dvl0) add_until(d_.dvl0->samples, dvl_, t_ns, est, published);
    if (d_.pressure0) add_until(*d_.pressure0, depth_, t_ns, est, published);
    if (d_.imu0) add_until(*d_.imu0, att_, t_ns, est, published);
  }

 private:
  template <class Sample>
  static void add_until(const std::vector<Sample>& samples, size_t& next, int64_t t_ns,
                        global_pose::GlobalPoseEstimator& est,
                        global_pose::PublishedGlobalPose* published) {
    for (; next < samples.size() && samples[next].timestamp_ns <= t_ns; ++next) {
      est.add(samples[next]);
      if (published) published->add(samples[next]);
    }
  }

  const Dataset& d_;
  size_t dvl_ = 0, depth_ = 0, att_ = 0;
};

global_pose::NetObservation observation(int64_t t_ns, const NetDetection& d) {
  global_pose::NetObservation obs;
  obs.t_ns = t_ns;
  for (const RoiNetPoint& p : d.points) {
    obs.points_C.push_back(p.valid() ? p.p_C : Eigen::Vector3d::Constant(kNaN));
    obs.quality.push_back(p.valid() ? std::max(p.quality, 1e-6) : 1.0);
  }
  if (d.pose.valid()) {
    obs.d_net_m = d.pose.d_net_m;
    obs.psi_net_rad = d.pose.psi_net_rad;
  }
  return obs;
}

void fill_global_pose(EstimateRow& row, const global_pose::GlobalPose& g) {
  row.r_g_m = g.r_g_m;
  row.rho_g_rad = g.rho_g_rad;
  row.z_g_m = g.z_g_m;
  row.psi_g_rad = g.psi_g_rad;
}

}  // namespace

RunSummary run_dataset(const Dataset& dataset, const std::filesystem::path& out_dir,
                       const RunOptions& options) {
  RunSummary summary;
  NetDetectorConfig config = options.detector;
  config.mesh_m = dataset.scene.net_mesh_size_m;
  NetDetector detector(dataset.cam0.camera, config);
  summary.backend = detector.description();

  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create output folder " + out_dir.string() + ": " + ec.message());
  EstimatesCsvWriter estimates(out_dir / "estimates.csv");
  global_pose::GlobalPoseEstimator global_pose(global_pose_config(dataset));
  std::optional<global_pose::PublishedGlobalPose> published;
  std::optional<GlobalPoseCsvWriter> published_csv;
  if (options.write_published_global_pose) {
    published.emplace(published_config(dataset));
    published_csv.emplace(out_dir / kPublishedGlobalPoseFile);
  }
  SensorFeed feed(dataset);

  const size_t total = dataset.frames.size();
  for (size_t i = 0; i < total; ++i) {
    EstimateRow row, published_row;
    row.timestamp_ns = published_row.timestamp_ns = dataset.frames[i].timestamp_ns;
    Stopwatch sw;
    try {
      const ImageU8 frame = dataset.load_frame(i);
      summary.times.add("load image", sw.elapsed_ms());
      const NetDetection d = detector.detect(frame, row.timestamp_ns);
      summary.times.add("fft net detection", d.fft_ms);
      summary.times.add("relative pose (fft)", d.pose_ms);
      row.valid_rois = d.pose.valid_rois;
      if (d.pose.valid()) {
        row.d_net_fft_m = d.pose.d_net_m;
        row.psi_net_fft_rad = d.pose.psi_net_rad;
        row.pitch_net_fft_rad = d.pose.pitch_net_rad;
      } else {
        ++summary.frames_without_pose;
      }
      sw.restart();
      feed.until(row.timestamp_ns, global_pose, published ? &*published : nullptr);
      const global_pose::NetObservation obs = observation(row.timestamp_ns, d);
      global_pose.add(obs);
      fill_global_pose(row, global_pose.estimate(row.timestamp_ns));
      summary.times.add("global pose", sw.elapsed_ms());
      if (published) fill_global_pose(published_row, published->add(obs));
    } catch (const Error& e) {
      log_warning("frame " + std::to_string(i) + " skipped (NaN row): " + e.what());
      ++summary.frames_skipped;
    }
    estimates.write(row);
    if (published_csv) published_csv->write(published_row);
    ++summary.frames;
    if (options.on_progress) options.on_progress(i + 1, total);
  }
  estimates.finish();
  if (published_csv) published_csv->finish();
  summary.global_pose_counters = global_pose::describe(global_pose.counters());
  return summary;
}

}  // namespace pensight
