#include "pipeline/dataset/global_pose_csv.h"

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"

namespace pensight {

GlobalPoseCsvWriter::GlobalPoseCsvWriter(const std::filesystem::path& file)
    : file_(std::make_unique<AtomicFile>(file)) {
  file_->stream() << "#timestamp [ns],r_g [m],rho_g [rad],z_g [m],psi_g [rad]\n";
}

GlobalPoseCsvWriter::~GlobalPoseCsvWriter() = default;

void GlobalPoseCsvWriter::write(const EstimateRow& r) {
  if (!file_) throw Error("GlobalPoseCsvWriter::write after finish");
  std::ostream& out = file_->stream();
  out << r.timestamp_ns;
  for (const double v : {r.r_g_m, r.rho_g_rad, r.z_g_m, r.psi_g_rad})
    out << "," << format_number(v);
  out << "\n";
}

void GlobalPoseCsvWriter::finish() {
  if (!file_) throw Error("GlobalPoseCsvWriter::finish called twice");
  file_->commit();
  file_.reset();
}

std::vector<EstimateRow> read_global_pose_csv(const std::filesystem::path& file) {
  const CsvTable t(file, 5, 5);
  std::vector<EstimateRow> rows;
  for (size_t i = 0; i < t.rows(); ++i) {
    EstimateRow r;
    r.timestamp_ns = t.integer(i, 0);
    r.r_g_m = t.number(i, 1);
    r.rho_g_rad = t.number(i, 2);
    r.z_g_m = t.number(i, 3);
    r.psi_g_rad = t.number(i, 4);
    rows.push_back(r);
  }
  return rows;
}

}  // namespace pensight
