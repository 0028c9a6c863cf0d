#pragma once
// OUT/report.html: one self-contained page (inline SVG plots, overlay PNGs as data: URIs, nothing
// fetched) that a user opens after `pensight run`. docs/report.md lists what it shows and the
// files it reads.
#include <filesystem>

#include "pipeline/dataset/dataset_reader.h"

namespace pensight {

// Reads what a run left in out_dir and writes out_dir/report.html. `dataset` (may be null) adds
// the ground truth and the error summary of `pensight evaluate` when it has groundtruth0, and
// the pen circle to the top view. Optional files that are absent (or unreadable) become sections
// that say so. Throws pensight::Error naming out_dir/estimates.csv when it is missing or
// malformed. `input`, when given, is what the user ran on where that was not the dataset folder
// (a bag converted into a temporary dataset for the run): the page names it instead.
void write_report_html(const std::filesystem::path& out_dir, const Dataset* dataset,
                       const std::filesystem::path& input = {});

}  // namespace pensight
