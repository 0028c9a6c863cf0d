#pragma once
// OUT/diagnostics.csv of `pensight run` (../shared/dataset-format.md, version 1.1): one row per
// camera frame saying why an estimate is what it is. Columns (docs/runtime.md, "Outputs of
// `pensight run`"):
//   #timestamp [ns],valid_rois,inlier_rois,plane_rms [m],fft_reason,mesh_angle [deg],
//   dvl_plane_d [m],dvl_plane_psi [rad], then <sensor>_accepted,<sensor>_rejected for each of
//   dvl_velocity, dvl_plane, depth, attitude, vision_fix, vision_relative, net_texture; then
//   mesh_type, reduced_rois, depth_scale (the scale applied to the frame's dense depth: the
//   DVL's measure of the bar length when engaged, else 1; nan without dense depth),
//   dvl_depth_ratio (the DVL's measure itself, the window median of its depth over the dense
//   depth's, engaged or not; nan until it has enough samples; dvl_depth_scale.h),
//   depth_psi_offset [rad], depth_pitch_offset [rad] (added to the dense depth's psi and pitch:
//   the DVL's measure of the net's tilt when engaged, else 0; nan without dense depth),
//   dvl_depth_psi_diff [rad], dvl_depth_pitch_diff [rad] (the DVL's measure itself, the window
//   median of the DVL plane's angle minus the dense depth's; nan until it has enough samples;
//   dvl_net_tilt.h), fft_quality (the FFT pose's quality in [0, 1], 0 without a pose;
//   relative_pose_fft.h)
// fft_reason is empty when the FFT pose is valid; commas in it are written as ';'. The sensor
// columns count the samples applied (accepted or re-locked) and refused (gated out or invalid)
// since the previous row. Written whole like estimates.csv.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "core/dataset_types.h"

namespace pensight {

inline constexpr const char* kDiagnosticsFile = "diagnostics.csv";
inline constexpr std::array<const char*, 7> kDiagnosticsSensors = {
    "dvl_velocity", "dvl_plane",       "depth",      "attitude",
    "vision_fix",   "vision_relative", "net_texture"};

struct DiagnosticsRow {
  int64_t timestamp_ns = 0;
  int valid_rois = 0;
  int inlier_rois = 0;
  double plane_rms_m = kNaN;
  std::string fft_reason;
  double mesh_angle_deg = kNaN;  // the detector's smoothed opening angle (mesh_angle.h)
  double dvl_plane_d_m = kNaN, dvl_plane_psi_rad = kNaN;
  std::array<int, kDiagnosticsSensors.size()> accepted = {}, rejected = {};  // in that order
  std::string mesh_type;  // "square" | "diamond"; empty for a skipped frame
  int reduced_rois = 0;   // ROIs whose spectral basis held a diagonal, reduced to the bars
  double depth_scale = kNaN, dvl_depth_ratio = kNaN;
  double depth_psi_offset_rad = kNaN, depth_pitch_offset_rad = kNaN;
  double dvl_depth_psi_diff_rad = kNaN, dvl_depth_pitch_diff_rad = kNaN;
  double fft_quality = 0;
};

class AtomicFile;

class DiagnosticsCsvWriter {
 public:
  explicit DiagnosticsCsvWriter(const std::filesystem::path& file);
  ~DiagnosticsCsvWriter();
  DiagnosticsCsvWriter(const DiagnosticsCsvWriter&) = delete;
  DiagnosticsCsvWriter& operator=(const DiagnosticsCsvWriter&) = delete;

  void write(const DiagnosticsRow& row);
  void finish();

 private:
  std::unique_ptr<AtomicFile> file_;
};

}  // namespace pensight
