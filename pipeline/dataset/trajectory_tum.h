#pragma once
// OUT/trajectory_tum.txt of `pensight run` (../shared/dataset-format.md): the body pose in P per
// camera frame in the TUM format that evo and similar tools read, one line per frame
//   t x y z qx qy qz qw
// t in seconds (the frame's timestamp_ns / 1e9, all nine decimals), x y z the body origin in P
// [m], q the unit quaternion of R_pen_body with qw >= 0 (q and -q are the same rotation: fixing the
// sign makes equal poses equal text); space-separated, no header. Frames without a pose (any
// element not finite, GlobalPose before the lock etc.) are left out. Written whole like
// estimates.csv.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace pensight {

inline constexpr const char* kTrajectoryTumFile = "trajectory_tum.txt";

// One line of the file, with its '\n'. The pose must be finite.
std::string tum_line(int64_t timestamp_ns, const Eigen::Isometry3d& T_pen_body);

class AtomicFile;

// Lines go to a temporary file that finish() renames to `file`; destroyed before finish(), the
// temporary file is removed and `file` is left as it was.
class TrajectoryTumWriter {
 public:
  explicit TrajectoryTumWriter(const std::filesystem::path& file);
  ~TrajectoryTumWriter();
  TrajectoryTumWriter(const TrajectoryTumWriter&) = delete;
  TrajectoryTumWriter& operator=(const TrajectoryTumWriter&) = delete;

  // Writes the frame's line; a pose with a non-finite element writes nothing (returns false).
  bool write(int64_t timestamp_ns, const Eigen::Isometry3d& T_pen_body);
  void finish();

 private:
  std::unique_ptr<AtomicFile> file_;
};

struct TumPose {
  int64_t timestamp_ns = 0;
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

// Reads a TUM trajectory as the tools that read it do: lines starting with '#' and blank lines
// are skipped, fields are separated by spaces or tabs. The timestamp is read to the nanosecond
// when it is written in fixed point. Throws pensight::Error naming the file and line when a line
// does not hold 8 numbers.
std::vector<TumPose> read_trajectory_tum(const std::filesystem::path& file);

}  // namespace pensight
