#include "pipeline/runner.h"

#include <string>

#include "pipeline/dataset/estimates_csv.h"
#include "runtime/error.h"
#include "runtime/log.h"

namespace pensight {

RunSummary run_dataset(const Dataset& dataset, const std::filesystem::path& out_dir,
                       const RunOptions& options) {
  RunSummary summary;
  summary.backend = resolve_backend(options.backend);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    throw Error("cannot create output folder " + out_dir.string() + ": " + ec.message());
  }
  EstimatesCsvWriter estimates(out_dir / "estimates.csv");

  const size_t total = dataset.frames.size();
  for (size_t i = 0; i < total; ++i) {
    EstimateRow row;
    row.timestamp_ns = dataset.frames[i].timestamp_ns;
    Stopwatch sw;
    try {
      const ImageU8 frame = dataset.load_frame(i);
      summary.times.add("load image", sw.elapsed_ms());
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
