#pragma once
// OUT/estimates.csv of `pensight run` (../shared/dataset-format.md): one row per camera frame,
// NaN (written `nan`) where an estimate is not available.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/dataset_types.h"

namespace pensight {

struct EstimateRow {
  int64_t timestamp_ns = 0;
  double d_net_fft_m = kNaN, psi_net_fft_rad = kNaN, pitch_net_fft_rad = kNaN;
  double d_net_depth_m = kNaN, psi_net_depth_rad = kNaN, pitch_net_depth_rad = kNaN;
  double r_g_m = kNaN, rho_g_rad = kNaN, z_g_m = kNaN, psi_g_rad = kNaN;
  int valid_rois = 0;
};

class AtomicFile;

// Rows go to a temporary file that finish() renames to `file`; destroyed before finish(), the
// temporary file is removed and `file` is left as it was.
class EstimatesCsvWriter {
 public:
  explicit EstimatesCsvWriter(const std::filesystem::path& file);
  ~EstimatesCsvWriter();
  EstimatesCsvWriter(const EstimatesCsvWriter&) = delete;
  EstimatesCsvWriter& operator=(const EstimatesCsvWriter&) = delete;

  void write(const EstimateRow& row);
  void finish();

 private:
  std::unique_ptr<AtomicFile> file_;
};

std::vector<EstimateRow> read_estimates_csv(const std::filesystem::path& file);

}  // namespace pensight
