#include "pipeline/dataset/estimates_csv.h"

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"

namespace pensight {

EstimatesCsvWriter::EstimatesCsvWriter(const std::filesystem::path& file)
    : file_(std::make_unique<AtomicFile>(file)) {
  file_->stream() << "#timestamp [ns],d_net_fft [m],psi_net_fft [rad],pitch_net_fft [rad],"
                     "d_net_depth [m],psi_net_depth [rad],pitch_net_depth [rad],r_g [m],"
                     "rho_g [rad],z_g [m],psi_g [rad],valid_rois\n";
}

EstimatesCsvWriter::~EstimatesCsvWriter() = default;

void EstimatesCsvWriter::write(const EstimateRow& r) {
  if (!file_) throw Error("EstimatesCsvWriter::write after finish");
  std::ostream& out = file_->stream();
  out << r.timestamp_ns;
  for (const double v :
       {r.d_net_fft_m, r.psi_net_fft_rad, r.pitch_net_fft_rad, r.d_net_depth_m, r.psi_net_depth_rad,
        r.pitch_net_depth_rad, r.r_g_m, r.rho_g_rad, r.z_g_m, r.psi_g_rad}) {
    out << "," << format_number(v);
  }
  out << "," << r.valid_rois << "\n";
}

void EstimatesCsvWriter::finish() {
  if (!file_) throw Error("EstimatesCsvWriter::finish called twice");
  file_->commit();
  file_.reset();
}

std::vector<EstimateRow> read_estimates_csv(const std::filesystem::path& file) {
  const CsvTable t(file, 12, 12);
  std::vector<EstimateRow> rows;
  for (size_t i = 0; i < t.rows(); ++i) {
    EstimateRow r;
    r.timestamp_ns = t.integer(i, 0);
    double* fields[] = {&r.d_net_fft_m,   &r.psi_net_fft_rad,   &r.pitch_net_fft_rad,
                        &r.d_net_depth_m, &r.psi_net_depth_rad, &r.pitch_net_depth_rad,
                        &r.r_g_m,         &r.rho_g_rad,         &r.z_g_m,
                        &r.psi_g_rad};
    for (size_t f = 0; f < 10; ++f) *fields[f] = t.number(i, f + 1);
    r.valid_rois = static_cast<int>(t.integer(i, 11));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace pensight
