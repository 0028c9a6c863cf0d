#pragma once
// The whole chain on a rendered sequence, for estimator tests against the synthetic world:
// scenario -> test_renderer() (1 sample per pixel) -> dataset in a temporary folder ->
// `pensight run`'s pipeline on the CPU backend -> estimates and trajectory. The folder is removed
// afterwards; the returned dataset keeps its ground truth (read up front) but no longer its images.
#include <memory>
#include <string>
#include <vector>

#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/trajectory_tum.h"
#include "sim/generate.h"
#include "sim/scenario.h"
#include "tools/runner.h"

namespace pensight::testing {

// scenarios/<file> of the source tree (CTest sets PENSIGHT_SOURCE_DIR), cut to duration_s when
// > 0, rendered with 1 sample per pixel to keep tests fast.
sim::Scenario shipped_scenario(const std::string& file, double duration_s = 0);

struct RenderedRun {
  Dataset dataset;
  std::vector<EstimateRow> rows;
  std::vector<TumPose> trajectory;  // OUT/trajectory_tum.txt
  RunSummary summary;
};

// The renderer of the rendered tests: the CPU reference, or with PENSIGHT_TEST_RENDERER=vulkan
// the Vulkan renderer on test_device(). scripts/test.sh takes Vulkan except under TSan: on
// lavapipe it is 8x faster than the reference (which under ASan is also instrumented, 15-20x
// slower), and the reference keeps its own checks in the renderer tests.
std::unique_ptr<sim::FrameRenderer> test_renderer(const sim::Scenario& s);

RenderedRun render_and_run(const sim::Scenario& s);

// The rendered dataset alone, to run the pipeline on it several times (e.g. with sensor samples
// changed in memory); its temporary folder lives as long as this does.
class RenderedDataset {
 public:
  explicit RenderedDataset(const sim::Scenario& s);
  ~RenderedDataset();
  RenderedDataset(const RenderedDataset&) = delete;
  RenderedDataset& operator=(const RenderedDataset&) = delete;

  const Dataset& dataset() const { return dataset_; }
  // The temporary folder holding the dataset (in data/); outputs may go beside it.
  const std::filesystem::path& dir() const { return dir_; }
  // `pensight run`'s pipeline (CPU backend) on `d` (this dataset or a changed copy of it), into
  // the output folder `name`; the published node's rows come in `published_rows`.
  RenderedRun run(const Dataset& d, const std::string& name,
                  std::vector<EstimateRow>* published_rows = nullptr) const;

 private:
  std::filesystem::path dir_;
  Dataset dataset_;
};

}  // namespace pensight::testing
