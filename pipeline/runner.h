#pragma once
// `pensight run`: the pipeline over every frame of a dataset, writing OUT/estimates.csv.
#include <cstddef>
#include <filesystem>
#include <functional>

#include "pipeline/backend.h"
#include "pipeline/dataset/dataset_reader.h"
#include "runtime/timing.h"

namespace pensight {

struct RunOptions {
  Backend backend = Backend::kAuto;
  // Called after each frame with (frames done, total frames).
  std::function<void(size_t, size_t)> on_progress;
};

struct RunSummary {
  ResolvedBackend backend;
  size_t frames = 0;
  size_t frames_skipped = 0;  // unreadable or wrong-size images: NaN rows, with a warning each
  StageTimes times;
};

// Writes out_dir/estimates.csv whole (temporary name, then rename), creating out_dir if needed.
// Throws pensight::Error for problems that affect the whole run (unwritable output, bad backend).
RunSummary run_dataset(const Dataset& dataset, const std::filesystem::path& out_dir,
                       const RunOptions& options);

}  // namespace pensight
