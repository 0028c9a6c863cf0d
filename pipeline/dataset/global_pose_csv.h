#pragma once
// OUT/global_pose_published.csv of `pensight run`: the published global-pose node's output per
// camera frame (the baseline the fused estimator in estimates.csv is compared with), written
// whole like estimates.csv. Columns:
//   #timestamp [ns],r_g [m],rho_g [rad],z_g [m],psi_g [rad]
#include <filesystem>
#include <memory>
#include <vector>

#include "pipeline/dataset/estimates_csv.h"

namespace pensight {

inline constexpr const char* kPublishedGlobalPoseFile = "global_pose_published.csv";

class AtomicFile;

// Rows go to a temporary file that finish() renames to `file`; destroyed before finish(), the
// temporary file is removed and `file` is left as it was.
class GlobalPoseCsvWriter {
 public:
  explicit GlobalPoseCsvWriter(const std::filesystem::path& file);
  ~GlobalPoseCsvWriter();
  GlobalPoseCsvWriter(const GlobalPoseCsvWriter&) = delete;
  GlobalPoseCsvWriter& operator=(const GlobalPoseCsvWriter&) = delete;

  // Writes the row's timestamp and r_g, rho_g, z_g, psi_g.
  void write(const EstimateRow& row);
  void finish();

 private:
  std::unique_ptr<AtomicFile> file_;
};

// The rows as EstimateRow with only the timestamp and the global-pose columns set (the rest NaN),
// so they score like estimates.csv. Throws pensight::Error naming the file, line and column.
std::vector<EstimateRow> read_global_pose_csv(const std::filesystem::path& file);

}  // namespace pensight
