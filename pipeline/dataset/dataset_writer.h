#pragma once
// Writing a dataset in the layout of ../shared/dataset-format.md, in one of two ways:
// - whole (renders, conversions): everything goes into a hidden temporary folder beside the
//   target, which finish() renames onto the target, so an interrupted or failed run never leaves
//   a folder that looks like a complete dataset;
// - streaming (live recordings): straight into the target, each row flushed as it is added and
//   each frame's PNG renamed into place before its row, so a killed recorder leaves a readable
//   dataset up to its last complete row.
#include <filesystem>
#include <fstream>
#include <optional>

#include "core/dataset_types.h"
#include "core/image.h"

namespace pensight {

// Which sensor folders the dataset has (an absent folder means the sensor is absent).
struct DatasetContents {
  SceneConfig scene;
  CameraCalibration cam0;
  std::optional<DvlCalibration> dvl0;
  bool dvl_beam_ranges = true;  // write the optional r1..r4 columns
  bool pressure0 = true;
  bool imu0 = true;
  bool groundtruth0 = true;  // data.csv and depth/
  // A `device_time [ns]` column after the contract's in dvl0, pressure0 and imu0: each sample's
  // raw time stamp from its device (nan where it has none); readers pass extra columns over.
  bool device_times = false;
};

enum class DatasetWriteMode { kWhole, kStreaming };

// One row of groundtruth0/mesh.csv, a pensight extra outside the shared contract (readers
// ignore it): the mesh at the optical axis's net hit (angle and stretch NaN where it misses).
struct MeshTruthRow {
  int64_t timestamp_ns = 0;
  MeshType mesh_type = MeshType::kSquare;
  double opening_angle_rad = kNaN;
  double stretch = kNaN;  // local bar length / nominal - 1
};

class DatasetWriter {
 public:
  // kWhole: `root` may be absent, an empty folder or an earlier dataset (it is replaced on
  // finish()); kStreaming: absent or an empty folder. Any other existing path is refused so that
  // no unrelated folder (or earlier recording) is ever overwritten.
  DatasetWriter(std::filesystem::path root, DatasetContents contents,
                DatasetWriteMode mode = DatasetWriteMode::kWhole);
  // kWhole: removes the temporary folder unless finish() succeeded.
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  // cam0 frame, stored as data/<timestamp_ns>.png; must match the calibration's size and come
  // after the previous frame.
  void add_frame(int64_t timestamp_ns, const ImageU8& image);
  // The same in colour (an RGB PNG; readers convert it to grey, png_io.h).
  void add_frame(int64_t timestamp_ns, const ImageRgb8& image);
  // Ground truth for the frame with the same timestamp: one data.csv row and its z-depth image
  // in millimetres (0 = no net).
  void add_groundtruth(const GroundTruthRow& row, const ImageU16& depth_mm);
  // Optional, after the frame's add_groundtruth; the first call creates groundtruth0/mesh.csv.
  void add_mesh_truth(const MeshTruthRow& row);
  void add_dvl(const DvlSample& sample);
  void add_pressure(const PressureSample& sample);
  void add_attitude(const AttitudeSample& sample);

  // Closes every file and (kWhole) moves the dataset to `root`.
  void finish();

  // Where the files are written until finish(): `root` itself when streaming.
  const std::filesystem::path& temporary_root() const { return temp_; }

 private:
  std::ofstream open_csv(const std::filesystem::path& rel, const std::string& header);
  void check_frame(const char* what, int64_t t, int64_t& last, int w, int h) const;
  template <class Pixel>
  void write_frame(int64_t timestamp_ns, const Image<Pixel>& image);
  void end_row(std::ofstream& csv, const std::optional<int64_t>& device_ns);

  std::filesystem::path root_;
  std::filesystem::path temp_;
  DatasetContents contents_;
  DatasetWriteMode mode_;
  std::ofstream cam_csv_, dvl_csv_, pressure_csv_, imu_csv_, gt_csv_, mesh_csv_;
  int64_t last_frame_ns_ = INT64_MIN, last_gt_ns_ = INT64_MIN, last_dvl_ns_ = INT64_MIN,
          last_pressure_ns_ = INT64_MIN, last_imu_ns_ = INT64_MIN, last_mesh_ns_ = INT64_MIN;
  bool finished_ = false;
};

// Frame file name used by DatasetWriter: "<timestamp_ns>.png".
std::string frame_filename(int64_t timestamp_ns);

}  // namespace pensight
