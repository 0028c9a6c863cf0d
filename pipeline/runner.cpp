#include "pipeline/runner.h"

#include <string>

#include "pipeline/dataset/estimates_csv.h"
#include "runtime/error.h"
#include "runtime/log.h"

namespace pensight {

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

  const size_t total = dataset.frames.size();
  for (size_t i = 0; i < total; ++i) {
    EstimateRow row;
    row.timestamp_ns = dataset.frames[i].timestamp_ns;
    Stopwatch sw;
    try {
      const ImageU8 frame = dataset.load_frame(i);
      summary.times.add("load image", sw.elapsed_ms());
      const NetDetection d = detector.detect(frame);
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
    } catch (const Error& e) {
      log_warning("frame " + std::to_string(i) + " skipped (NaN row): " + e.what());
      ++summary.frames_skipped;
    }
    estimates.write(row);
    ++summary.frames;
    if (options.on_progress) options.on_progress(i + 1, total);
  }
  estimates.finish();
  return summary;
}

}  // namespace pensight
