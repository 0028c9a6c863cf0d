#include "pipeline/dataset/diagnostics_csv.h"

#include <algorithm>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"

namespace pensight {

DiagnosticsCsvWriter::DiagnosticsCsvWriter(const std::filesystem::path& file)
    : file_(std::make_unique<AtomicFile>(file)) {
  std::ostream& out = file_->stream();
  out << "#timestamp [ns],valid_rois,inlier_rois,plane_rms [m],fft_reason,mesh_angle [deg],"
         "dvl_plane_d [m],dvl_plane_psi [rad]";
  for (const char* s : kDiagnosticsSensors) out << "," << s << "_accepted," << s << "_rejected";
  out << ",mesh_type,reduced_rois,depth_scale,dvl_depth_ratio,depth_psi_offset [rad],"
         "depth_pitch_offset [rad],dvl_depth_psi_diff [rad],dvl_depth_pitch_diff "
         "[rad],fft_quality\n";
}

DiagnosticsCsvWriter::~DiagnosticsCsvWriter() = default;

void DiagnosticsCsvWriter::write(const DiagnosticsRow& r) {
  if (!file_) throw Error("DiagnosticsCsvWriter::write after finish");
  std::string reason = r.fft_reason;
  std::replace(reason.begin(), reason.end(), ',', ';');
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  std::ostream& out = file_->stream();
  out << r.timestamp_ns << "," << r.valid_rois << "," << r.inlier_rois << ","
      << format_number(r.plane_rms_m) << "," << reason << "," << format_number(r.mesh_angle_deg)
      << "," << format_number(r.dvl_plane_d_m) << "," << format_number(r.dvl_plane_psi_rad);
  for (size_t i = 0; i < kDiagnosticsSensors.size(); ++i) {
    out << "," << r.accepted[i] << "," << r.rejected[i];
  }
  out << "," << r.mesh_type << "," << r.reduced_rois << "," << format_number(r.depth_scale) << ","
      << format_number(r.dvl_depth_ratio) << "," << format_number(r.depth_psi_offset_rad) << ","
      << format_number(r.depth_pitch_offset_rad) << "," << format_number(r.dvl_depth_psi_diff_rad)
      << "," << format_number(r.dvl_depth_pitch_diff_rad) << "," << format_number(r.fft_quality)
      << "\n";
}

void DiagnosticsCsvWriter::finish() {
  if (!file_) throw Error("DiagnosticsCsvWriter::finish called twice");
  file_->commit();
  file_.reset();
}

}  // namespace pensight
