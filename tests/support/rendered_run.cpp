#include "tests/support/rendered_run.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "pipeline/dataset/global_pose_csv.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::testing {
namespace {

namespace fs = std::filesystem;

// One folder per process and test; a parameterised test's name ("Name/0") names a file, not a
// subfolder, which would be left behind empty when the folder is removed.
fs::path fresh_folder() {
  std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::replace(name.begin(), name.end(), '/', '_');
  const fs::path dir =
      fs::temp_directory_path() / ("pensight_rendered_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Renders into dir/data; removes dir if that fails.
Dataset render_into(const fs::path& dir, const sim::Scenario& s) {
  try {
    const auto renderer = test_renderer(s);
    sim::generate_dataset(s, *renderer, dir / "data");
    return read_dataset(dir / "data");
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    throw;
  }
}

}  // namespace

std::unique_ptr<sim::FrameRenderer> test_renderer(const sim::Scenario& s) {
  const char* which = std::getenv("PENSIGHT_TEST_RENDERER");
  if (which == nullptr || std::string(which) == "cpu") return sim::make_cpu_renderer(s, {});
  if (std::string(which) != "vulkan")
    throw std::runtime_error(std::string("PENSIGHT_TEST_RENDERER=") + which +
                             ": unknown renderer (use cpu or vulkan)");
  return sim::make_renderer(s, {}, Backend::kVulkan, test_device());
}

sim::Scenario shipped_scenario(const std::string& file, double duration_s) {
  const char* root = std::getenv("PENSIGHT_SOURCE_DIR");
  sim::Scenario s =
      sim::load_scenario(std::filesystem::path(root ? root : ".") / "scenarios" / file);
  if (duration_s > 0) s.duration_s = duration_s;
  s.camera.samples_per_axis = 1;
  return s;
}

RenderedDataset::RenderedDataset(const sim::Scenario& s)
    : dir_(fresh_folder()), dataset_(render_into(dir_, s)) {}

RenderedDataset::~RenderedDataset() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

RenderedRun RenderedDataset::run(const Dataset& d, const std::string& name,
                                 std::vector<EstimateRow>* published_rows) const {
  RenderedRun run{d, {}, {}, {}};
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  options.write_published_global_pose = published_rows != nullptr;
  run.summary = run_dataset(d, dir_ / name, options, test_device());
  run.rows = read_estimates_csv(dir_ / name / "estimates.csv");
  run.trajectory = read_trajectory_tum(dir_ / name / kTrajectoryTumFile);
  if (published_rows)
    *published_rows = read_global_pose_csv(dir_ / name / kPublishedGlobalPoseFile);
  return run;
}

RenderedRun render_and_run(const sim::Scenario& s) {
  const RenderedDataset rendered(s);
  return rendered.run(rendered.dataset(), "out");
}

}  // namespace pensight::testing
