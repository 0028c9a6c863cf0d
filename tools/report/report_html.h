#pragma once
// OUT/report.html: one self-contained page (inline SVG plots, overlay PNGs as data: URIs, nothing
// fetched) that a user opens after `pensight run`. docs/report.md lists what it shows.
#include <filesystem>
#include <optional>
#include <vector>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/estimates_csv.h"
#include "tools/timing_table.h"

namespace pensight {

// What a run produced, as `pensight run` holds it while it writes OUT's CSVs: the report is built
// from these values, not from the files. An absent optional part is a section that says its file
// was not written by this run.
struct ReportInput {
  std::filesystem::path out_dir;  // the page goes here; overlays/*.png are read from here
  // Adds the ground truth and the error summary of `pensight evaluate` when it has groundtruth0,
  // and the pen circle to the top view; may be null.
  const Dataset* dataset = nullptr;
  // What the user ran on where that was not the dataset folder (a bag converted into a temporary
  // dataset for the run): the page names it instead.
  std::filesystem::path input;
  std::optional<std::vector<EstimateRow>> estimates;  // estimates.csv; required
  // global_pose_published.csv: the published node's rows (global-pose columns only).
  std::optional<std::vector<EstimateRow>> published;
  std::optional<std::vector<DiagnosticsRow>> diagnostics;  // diagnostics.csv
  std::optional<std::vector<TimingRow>> timing;            // timing.csv
};

// Writes input.out_dir/report.html. Throws pensight::Error naming out_dir when `estimates` is
// absent.
void write_report_html(const ReportInput& input);

}  // namespace pensight
