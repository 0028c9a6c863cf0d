#include "pipeline/dataset/dataset_writer.h"

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/dataset/png_io.h"

namespace pensight {
namespace fs = std::filesystem;
namespace {

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  if (!out) throw Error("cannot write '" + file.string() + "'");
}

void check_replaceable(const fs::path& root, DatasetWriteMode mode) {
  if (!fs::exists(root)) return;
  const bool is_dir = fs::is_directory(root);
  if (is_dir && fs::is_empty(root)) return;
  if (mode == DatasetWriteMode::kWhole && is_dir && fs::exists(root / "scene.yaml")) return;
  throw Error("output '" + root.string() + "' exists and is not " +
              (mode == DatasetWriteMode::kWhole ? "a dataset" : "empty") +
              "; choose another --out " + (is_dir ? "folder" : "path") + " or remove it");
}

// The header of a sensor log, with the device-time column when asked for.
std::string log_header(std::string header, bool device_times) {
  return device_times ? header + ",device_time [ns]" : header;
}

}  // namespace

std::string frame_filename(int64_t timestamp_ns) {
  return std::to_string(timestamp_ns) + ".png";
}

DatasetWriter::DatasetWriter(fs::path root, DatasetContents contents, DatasetWriteMode mode)
    : root_(std::move(root)), contents_(std::move(contents)), mode_(mode) {
  if (root_.filename().empty()) root_ = root_.parent_path();  // "out/" -> "out"
  check_replaceable(root_, mode_);
  if (!root_.parent_path().empty() && !fs::is_directory(root_.parent_path())) {
    throw Error("cannot write dataset '" + root_.string() + "': folder '" +
                root_.parent_path().string() + "' does not exist");
  }
  temp_ = mode_ == DatasetWriteMode::kWhole ? temporary_sibling(root_) : root_;
  std::error_code ec;
  fs::create_directories(temp_ / "cam0" / "data", ec);
  if (ec) throw Error("cannot create '" + temp_.string() + "': " + ec.message());

  write_text(temp_ / "scene.yaml", scene_yaml(contents_.scene));
  write_text(temp_ / "cam0" / "sensor.yaml", camera_yaml(contents_.cam0));
  cam_csv_ = open_csv("cam0/data.csv", "#timestamp [ns],filename");
  if (contents_.dvl0) {
    fs::create_directories(temp_ / "dvl0");
    write_text(temp_ / "dvl0" / "sensor.yaml", dvl_yaml(*contents_.dvl0));
    dvl_csv_ = open_csv("dvl0/data.csv",
                        log_header(contents_.dvl_beam_ranges
                                       ? "#timestamp [ns],vx [m/s],vy [m/s],vz [m/s],valid,r1 "
                                         "[m],r2 [m],r3 [m],r4 [m]"
                                       : "#timestamp [ns],vx [m/s],vy [m/s],vz [m/s],valid",
                                   contents_.device_times));
  }
  if (contents_.pressure0) {
    fs::create_directories(temp_ / "pressure0");
    pressure_csv_ = open_csv("pressure0/data.csv",
                             log_header("#timestamp [ns],depth [m]", contents_.device_times));
  }
  if (contents_.imu0) {
    fs::create_directories(temp_ / "imu0");
    imu_csv_ = open_csv(
        "imu0/attitude.csv",
        log_header("#timestamp [ns],roll [rad],pitch [rad],yaw [rad]", contents_.device_times));
  }
  if (contents_.groundtruth0) {
    fs::create_directories(temp_ / "groundtruth0" / "depth");
    gt_csv_ = open_csv("groundtruth0/data.csv",
                       "#timestamp [ns],x [m],y [m],z [m],roll [rad],pitch [rad],yaw [rad],"
                       "d_net [m],psi_net [rad],pitch_net [rad],net_fraction");
  }
}

DatasetWriter::~DatasetWriter() {
  if (finished_ || mode_ == DatasetWriteMode::kStreaming) return;
  std::error_code ec;
  fs::remove_all(temp_, ec);
}

std::ofstream DatasetWriter::open_csv(const fs::path& rel, const std::string& header) {
  std::ofstream out(temp_ / rel);
  out << header << "\n";
  if (mode_ == DatasetWriteMode::kStreaming) out.flush();
  if (!out) throw Error("cannot write '" + (temp_ / rel).string() + "'");
  return out;
}

// A row is handed to the file in one write when streaming: a killed process leaves whole rows.
void DatasetWriter::end_row(std::ofstream& csv, const std::optional<int64_t>& device_ns) {
  if (contents_.device_times) {
    csv << "," << (device_ns ? std::to_string(*device_ns) : std::string("nan"));
  }
  csv << "\n";
  if (mode_ == DatasetWriteMode::kStreaming) csv.flush();
  if (!csv) throw Error("writing dataset '" + temp_.string() + "' failed (disk full?)");
}

void DatasetWriter::check_frame(const char* what, int64_t t, int64_t& last, int w, int h) const {
  if (t <= last) throw Error(std::string(what) + ": timestamps must increase");
  const PinholeCamera& cam = contents_.cam0.camera;
  check_image_size(w, h, cam, what);
  last = t;
}

template <class Pixel>
void DatasetWriter::write_frame(int64_t timestamp_ns, const Image<Pixel>& image) {
  check_frame("DatasetWriter::add_frame", timestamp_ns, last_frame_ns_, image.width, image.height);
  const std::string name = frame_filename(timestamp_ns);
  const fs::path file = temp_ / "cam0" / "data" / name;
  if (mode_ == DatasetWriteMode::kStreaming) {
    // Hidden until complete, so the folder never holds a truncated frame under its own name.
    const fs::path partial = file.parent_path() / ("." + name);
    write_png(partial, image);
    std::error_code ec;
    fs::rename(partial, file, ec);
    if (ec) throw Error("cannot move '" + partial.string() + "' into place: " + ec.message());
  } else {
    write_png(file, image);
  }
  cam_csv_ << timestamp_ns << "," << name << "\n";
  if (mode_ == DatasetWriteMode::kStreaming) cam_csv_.flush();
}

void DatasetWriter::add_frame(int64_t timestamp_ns, const ImageU8& image) {
  write_frame(timestamp_ns, image);
}

void DatasetWriter::add_frame(int64_t timestamp_ns, const ImageRgb8& image) {
  write_frame(timestamp_ns, image);
}

void DatasetWriter::add_groundtruth(const GroundTruthRow& r, const ImageU16& depth_mm) {
  if (!contents_.groundtruth0) throw Error("DatasetWriter: groundtruth0 was not requested");
  check_frame("DatasetWriter::add_groundtruth", r.timestamp_ns, last_gt_ns_, depth_mm.width,
              depth_mm.height);
  write_png(temp_ / "groundtruth0" / "depth" / frame_filename(r.timestamp_ns), depth_mm);
  gt_csv_ << r.timestamp_ns;
  for (const double v :
       {r.p_pen_body_m.x(), r.p_pen_body_m.y(), r.p_pen_body_m.z(), r.roll_rad, r.pitch_rad,
        r.yaw_rad, r.d_net_m, r.psi_net_rad, r.pitch_net_rad, r.net_fraction}) {
    gt_csv_ << "," << format_number(v);
  }
  gt_csv_ << "\n";
}

void DatasetWriter::add_mesh_truth(const MeshTruthRow& r) {
  if (!contents_.groundtruth0) throw Error("DatasetWriter: groundtruth0 was not requested");
  if (r.timestamp_ns <= last_mesh_ns_) {
    throw Error("DatasetWriter::add_mesh_truth: timestamps must increase");
  }
  last_mesh_ns_ = r.timestamp_ns;
  if (!mesh_csv_.is_open()) {
    mesh_csv_ =
        open_csv("groundtruth0/mesh.csv", "#timestamp [ns],mesh_type,opening_angle [deg],stretch");
  }
  mesh_csv_ << r.timestamp_ns << "," << to_string(r.mesh_type) << ","
            << format_number(rad_to_deg(r.opening_angle_rad)) << "," << format_number(r.stretch)
            << "\n";
}

void DatasetWriter::add_dvl(const DvlSample& s) {
  if (!contents_.dvl0) throw Error("DatasetWriter: dvl0 was not requested");
  if (s.timestamp_ns <= last_dvl_ns_)
    throw Error("DatasetWriter::add_dvl: timestamps must increase");
  last_dvl_ns_ = s.timestamp_ns;
  dvl_csv_ << s.timestamp_ns << "," << format_number(s.velocity_B_mps.x()) << ","
           << format_number(s.velocity_B_mps.y()) << "," << format_number(s.velocity_B_mps.z())
           << "," << (s.valid ? 1 : 0);
  if (contents_.dvl_beam_ranges) {
    for (const double r : s.beam_range_m) dvl_csv_ << "," << format_number(r);
  }
  end_row(dvl_csv_, s.device_ns);
}

void DatasetWriter::add_pressure(const PressureSample& s) {
  if (!contents_.pressure0) throw Error("DatasetWriter: pressure0 was not requested");
  if (s.timestamp_ns <= last_pressure_ns_) {
    throw Error("DatasetWriter::add_pressure: timestamps must increase");
  }
  last_pressure_ns_ = s.timestamp_ns;
  pressure_csv_ << s.timestamp_ns << "," << format_number(s.depth_m);
  end_row(pressure_csv_, s.device_ns);
}

void DatasetWriter::add_attitude(const AttitudeSample& s) {
  if (!contents_.imu0) throw Error("DatasetWriter: imu0 was not requested");
  if (s.timestamp_ns <= last_imu_ns_) {
    throw Error("DatasetWriter::add_attitude: timestamps must increase");
  }
  last_imu_ns_ = s.timestamp_ns;
  imu_csv_ << s.timestamp_ns << "," << format_number(s.roll_rad) << ","
           << format_number(s.pitch_rad) << "," << format_number(s.yaw_rad);
  end_row(imu_csv_, s.device_ns);
}

void DatasetWriter::finish() {
  if (finished_) throw Error("DatasetWriter::finish called twice");
  for (std::ofstream* f : {&cam_csv_, &dvl_csv_, &pressure_csv_, &imu_csv_, &gt_csv_, &mesh_csv_}) {
    if (!f->is_open()) continue;
    f->flush();
    if (!*f) throw Error("writing dataset '" + temp_.string() + "' failed (disk full?)");
    f->close();
  }
  if (mode_ == DatasetWriteMode::kStreaming) {
    finished_ = true;
    return;
  }
  // Move an earlier dataset aside first: rename cannot replace a non-empty folder.
  const fs::path old = temporary_sibling(root_);
  const bool replace = fs::exists(root_);
  std::error_code ec;
  if (replace) {
    fs::rename(root_, old, ec);
    if (ec) throw Error("cannot replace '" + root_.string() + "': " + ec.message());
  }
  fs::rename(temp_, root_, ec);
  if (ec)
    throw Error("cannot move '" + temp_.string() + "' to '" + root_.string() +
                "': " + ec.message());
  finished_ = true;
  if (replace) fs::remove_all(old, ec);
}

}  // namespace pensight
