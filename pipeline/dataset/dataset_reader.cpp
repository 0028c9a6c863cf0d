#include "pipeline/dataset/dataset_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/csv.h"
#include "core/error.h"
#include "core/log.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/png_io.h"

namespace pensight {
namespace fs = std::filesystem;
namespace {

template <class T>
void require_time_order(const std::vector<T>& v, const fs::path& file) {
  for (size_t i = 1; i < v.size(); ++i) {
    if (v[i].timestamp_ns <= v[i - 1].timestamp_ns) {
      throw Error(file.string() + ": timestamps must increase (row " + std::to_string(i + 1) +
                  " repeats or goes back in time)");
    }
  }
}

// Columns after the contract's (a recorder's device times, another tool's extras) are passed over,
// said once per file.
constexpr size_t kAnyFields = std::numeric_limits<size_t>::max();

void note_extra_columns(const CsvTable& t, size_t contract_fields) {
  for (size_t r = 0; r < t.rows(); ++r) {
    if (t.fields(r) <= contract_fields) continue;
    log_info(t.file() + ": columns after the first " + std::to_string(contract_fields) +
             " are not part of the dataset contract; passed over");
    return;
  }
}

std::vector<ImageEntry> read_frames(const fs::path& file) {
  const CsvTable t(file, 2, kAnyFields);
  note_extra_columns(t, 2);
  std::vector<ImageEntry> out;
  for (size_t r = 0; r < t.rows(); ++r) out.push_back({t.integer(r, 0), t.text(r, 1)});
  // A run over no frames would write a header-only estimates.csv that looks like a result.
  if (out.empty()) {
    throw Error(file.string() +
                ": lists no camera frames; add one row '<timestamp ns>,<file name>' per image");
  }
  require_time_order(out, file);
  return out;
}

// Reads the rows of a sensor log with `parse`, skipping a row that parse throws on (a field that
// is not a number) or whose timestamp does not increase, as well as the rows the table set aside.
// Throws when more than kMaxSkippedRowFraction of the rows are bad, naming the first bad one.
template <class Sample, class Parse>
std::vector<Sample> read_log(const CsvTable& t, Parse parse, std::vector<SkippedRows>& skipped) {
  constexpr size_t kWarningsPerFile = 5;
  std::vector<CsvTable::Rejected> bad = t.rejected();
  std::vector<Sample> out;
  for (size_t r = 0; r < t.rows(); ++r) {
    try {
      Sample s = parse(r);
      if (!out.empty() && s.timestamp_ns <= out.back().timestamp_ns) {
        bad.push_back({t.line(r), t.file() + ":" + std::to_string(t.line(r)) +
                                      ": timestamp repeats or goes back in time"});
        continue;
      }
      out.push_back(s);
    } catch (const Error& e) {
      bad.push_back({t.line(r), e.what()});
    }
  }
  if (bad.empty()) return out;
  std::sort(bad.begin(), bad.end(), [](const auto& a, const auto& b) { return a.line < b.line; });
  const size_t rows = out.size() + bad.size();
  const std::string counted = std::to_string(bad.size()) + " of " + std::to_string(rows) + " rows";
  if (static_cast<double>(bad.size()) > kMaxSkippedRowFraction * static_cast<double>(rows)) {
    throw Error(bad.front().message + " (" + counted +
                " are bad: check that the file is in the layout of dataset-format.md)");
  }
  for (size_t i = 0; i < std::min(bad.size(), kWarningsPerFile); ++i) {
    log_warning(bad[i].message + "; row skipped");
  }
  log_warning(t.file() + ": " + counted + " skipped");
  skipped.push_back({t.file(), bad.size(), rows});
  return out;
}

DvlData read_dvl(const fs::path& dir, std::vector<SkippedRows>& skipped) {
  DvlData d;
  d.calibration = read_dvl_yaml(dir / "sensor.yaml");
  const CsvTable t(dir / "data.csv", 5, kAnyFields, BadRows::kSetAside);
  // Beam ranges are a property of the file: its header names r1 after `valid`, or (no header) its
  // well-formed rows have 9 fields. Further columns are passed over.
  const std::vector<std::string>& header = t.header();
  if (header.size() > 5) {
    d.has_beam_ranges = header[5].rfind("r1", 0) == 0;
  } else {
    for (size_t r = 0; r < t.rows() && !d.has_beam_ranges; ++r) {
      d.has_beam_ranges = t.fields(r) == 9;
    }
  }
  const size_t fields = d.has_beam_ranges ? 9 : 5;
  note_extra_columns(t, fields);
  d.samples = read_log<DvlSample>(
      t,
      [&](size_t r) {
        if (t.fields(r) != 5 && t.fields(r) < fields) {
          throw Error(t.file() + ":" + std::to_string(t.line(r)) +
                      ": expected 5 fields, or 9 with the beam ranges r1..r4");
        }
        DvlSample s;
        s.timestamp_ns = t.integer(r, 0);
        s.velocity_B_mps = {t.number(r, 1), t.number(r, 2), t.number(r, 3)};
        s.valid = t.integer(r, 4) != 0;
        if (d.has_beam_ranges && t.fields(r) >= 9) {
          for (size_t b = 0; b < 4; ++b) s.beam_range_m[b] = t.number(r, 5 + b);
        }
        return s;
      },
      skipped);
  return d;
}

std::vector<PressureSample> read_pressure(const fs::path& file, std::vector<SkippedRows>& skipped) {
  const CsvTable t(file, 2, kAnyFields, BadRows::kSetAside);
  note_extra_columns(t, 2);
  return read_log<PressureSample>(
      t,
      [&](size_t r) {
        return PressureSample{t.integer(r, 0), t.number(r, 1)};
      },
      skipped);
}

std::vector<AttitudeSample> read_attitude(const fs::path& file, std::vector<SkippedRows>& skipped) {
  const CsvTable t(file, 4, kAnyFields, BadRows::kSetAside);
  note_extra_columns(t, 4);
  return read_log<AttitudeSample>(
      t,
      [&](size_t r) {
        return AttitudeSample{t.integer(r, 0), t.number(r, 1), t.number(r, 2), t.number(r, 3)};
      },
      skipped);
}

GroundTruth read_groundtruth(const fs::path& dir) {
  GroundTruth g;
  const fs::path file = dir / "data.csv";
  const CsvTable t(file, 11, 11);
  for (size_t r = 0; r < t.rows(); ++r) {
    GroundTruthRow row;
    row.timestamp_ns = t.integer(r, 0);
    row.p_pen_body_m = {t.number(r, 1), t.number(r, 2), t.number(r, 3)};
    row.roll_rad = t.number(r, 4);
    row.pitch_rad = t.number(r, 5);
    row.yaw_rad = t.number(r, 6);
    row.d_net_m = t.number(r, 7);
    row.psi_net_rad = t.number(r, 8);
    row.pitch_net_rad = t.number(r, 9);
    row.net_fraction = t.number(r, 10);
    g.rows.push_back(row);
  }
  require_time_order(g.rows, file);
  g.has_depth = fs::is_directory(dir / "depth");
  return g;
}

}  // namespace

Dataset read_dataset(const fs::path& root) {
  if (!fs::is_directory(root)) {
    throw Error("dataset folder '" + root.string() + "' not found");
  }
  if (!fs::is_directory(root / "cam0")) {
    throw Error("'" + root.string() +
                "' has no cam0/ folder: not a dataset in the layout of "
                "dataset-format.md");
  }
  Dataset d;
  d.root = root;
  d.scene = read_scene_yaml(root / "scene.yaml");
  d.cam0 = read_camera_yaml(root / "cam0" / "sensor.yaml");
  d.frames = read_frames(root / "cam0" / "data.csv");
  if (fs::is_directory(root / "dvl0")) d.dvl0 = read_dvl(root / "dvl0", d.skipped_rows);
  if (fs::is_directory(root / "pressure0")) {
    d.pressure0 = read_pressure(root / "pressure0" / "data.csv", d.skipped_rows);
  }
  if (fs::is_directory(root / "imu0")) {
    d.imu0 = read_attitude(root / "imu0" / "attitude.csv", d.skipped_rows);
  }
  if (fs::is_directory(root / "groundtruth0")) {
    d.groundtruth0 = read_groundtruth(root / "groundtruth0");
  }
  return d;
}

ImageU8 Dataset::load_frame(size_t i) const {
  if (i >= frames.size()) throw Error("frame index out of range");
  return read_png_grey8(root / "cam0" / "data" / frames[i].filename, cam0.camera.width_px,
                        cam0.camera.height_px);
}

ImageU16 Dataset::load_depth_mm(size_t i) const {
  if (i >= frames.size()) throw Error("frame index out of range");
  if (!groundtruth0 || !groundtruth0->has_depth) {
    throw Error("'" + root.string() + "' has no groundtruth0/depth/ folder");
  }
  return read_png_u16(root / "groundtruth0" / "depth" / frames[i].filename, cam0.camera.width_px,
                      cam0.camera.height_px);
}

ImageU16 depth_mm_from_m(const ImageF32& depth_m) {
  ImageU16 mm(depth_m.width, depth_m.height);
  std::transform(depth_m.pixels.begin(), depth_m.pixels.end(), mm.pixels.begin(), [](float z) {
    return std::isfinite(z) && z > 0
               ? static_cast<uint16_t>(std::clamp(std::lround(z * 1000.0), 0L, 65535L))
               : uint16_t{0};
  });
  return mm;
}

ImageF32 depth_m_from_mm(const ImageU16& mm) {
  ImageF32 out(mm.width, mm.height);
  std::transform(mm.pixels.begin(), mm.pixels.end(), out.pixels.begin(),
                 [](uint16_t v) { return v == 0 ? std::nanf("") : static_cast<float>(v) * 1e-3f; });
  return out;
}

ImageF32 Dataset::load_depth_m(size_t i) const {
  return depth_m_from_mm(load_depth_mm(i));
}

const GroundTruthRow* Dataset::truth_for_frame(size_t i) const {
  if (!groundtruth0 || i >= frames.size()) return nullptr;
  const auto& rows = groundtruth0->rows;
  const auto it =
      std::lower_bound(rows.begin(), rows.end(), frames[i].timestamp_ns,
                       [](const GroundTruthRow& r, int64_t t) { return r.timestamp_ns < t; });
  return it != rows.end() && it->timestamp_ns == frames[i].timestamp_ns ? &*it : nullptr;
}

}  // namespace pensight
