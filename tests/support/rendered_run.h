#pragma once
// The whole chain on a rendered sequence, for estimator tests against the synthetic world:
// scenario -> CPU reference renderer (1 sample per pixel) -> dataset in a temporary folder ->
// `pensight run`'s pipeline on the CPU backend -> estimates. The folder is removed afterwards;
// the returned dataset keeps its ground truth (read up front) but no longer its images.
#include <string>
#include <vector>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/runner.h"
#include "sim/scenario.h"

namespace pensight::testing {

// scenarios/<file> of the source tree (CTest sets PENSIGHT_SOURCE_DIR), cut to duration_s when
// > 0, rendered with 1 sample per pixel to keep tests fast.
sim::Scenario shipped_scenario(const std::string& file, double duration_s = 0);

struct RenderedRun {
  Dataset dataset;
  std::vector<EstimateRow> rows;
  RunSummary summary;
};

RenderedRun render_and_run(const sim::Scenario& s);

}  // namespace pensight::testing
