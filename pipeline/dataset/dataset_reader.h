#pragma once
// Reading a dataset in the layout of ../shared/dataset-format.md. Everything but the images is
// read up front; images are loaded one at a time on request.
#include <filesystem>
#include <optional>
#include <vector>

#include "core/dataset_types.h"
#include "core/image.h"

namespace pensight {

// Rows of a sensor log (dvl0, pressure0, imu0) that read_dataset skipped: a wrong field count, a
// field that is not a number, or a timestamp that does not increase.
struct SkippedRows {
  std::filesystem::path file;
  size_t skipped = 0;
  size_t rows = 0;  // data rows in the file, skipped ones included
};

// A sensor log fails to read when more than this fraction of its rows is bad: then the file is
// not glitched but in another format, and skipping would hide that.
inline constexpr double kMaxSkippedRowFraction = 0.5;

struct DvlData {
  DvlCalibration calibration;
  std::vector<DvlSample> samples;
  bool has_beam_ranges = false;  // data.csv has the optional r1..r4 columns
};

struct GroundTruth {
  std::vector<GroundTruthRow> rows;
  bool has_depth = false;  // groundtruth0/depth/ exists
};

class Dataset {
 public:
  std::filesystem::path root;
  SceneConfig scene;
  CameraCalibration cam0;
  std::vector<ImageEntry> frames;  // in time order
  // Absent sensor folders are nullopt.
  std::optional<DvlData> dvl0;
  std::optional<std::vector<PressureSample>> pressure0;
  std::optional<std::vector<AttitudeSample>> imu0;
  std::optional<GroundTruth> groundtruth0;
  // One entry per sensor log with skipped rows; empty when every row was read.
  std::vector<SkippedRows> skipped_rows;

  // Frame i as 8-bit grey (colour and 16-bit PNGs are converted); throws pensight::Error when the
  // file is missing or its size differs from cam0/sensor.yaml.
  ImageU8 load_frame(size_t i) const;
  // Ground-truth z-depth of frame i in millimetres (0 = no net); requires groundtruth0/depth/.
  ImageU16 load_depth_mm(size_t i) const;
  // The same in metres, NaN where there is no net.
  ImageF32 load_depth_m(size_t i) const;
  // The ground-truth row with the timestamp of frame i, or nullptr.
  const GroundTruthRow* truth_for_frame(size_t i) const;
};

// A depth PNG of the contract (16-bit z-depth in millimetres, 0 = none) in metres, NaN where none.
ImageF32 depth_m_from_mm(const ImageU16& mm);
// The contract's depth PNG from metres: rounded to mm, clamped to 65535; 0 where the depth is
// not finite or not positive (no estimate).
ImageU16 depth_mm_from_m(const ImageF32& depth_m);

// Reads scene.yaml, cam0/ (required) and the optional sensor folders. Throws pensight::Error
// naming the file (and line or key) for anything missing or malformed, except single bad rows of
// the sensor logs: those are skipped, counted in skipped_rows and logged as warnings naming file
// and line (the first 5 per file, then a count), unless more than kMaxSkippedRowFraction of a
// log's rows are bad.
Dataset read_dataset(const std::filesystem::path& root);

}  // namespace pensight
