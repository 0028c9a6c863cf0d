#include "tests/support/rendered_run.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "sim/generate.h"

namespace pensight::testing {

sim::Scenario shipped_scenario(const std::string& file, double duration_s) {
  const char* root = std::getenv("PENSIGHT_SOURCE_DIR");
  sim::Scenario s =
      sim::load_scenario(std::filesystem::path(root ? root : ".") / "scenarios" / file);
  if (duration_s > 0) s.duration_s = duration_s;
  s.camera.samples_per_axis = 1;
  return s;
}

RenderedRun render_and_run(const sim::Scenario& s) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("pensight_rendered_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};

  const auto renderer = sim::make_cpu_renderer(s, {});
  sim::generate_dataset(s, *renderer, dir / "data");
  RenderedRun run{read_dataset(dir / "data"), {}, {}};
  RunOptions options;
  options.detector.backend = Backend::kCpu;
  run.summary = run_dataset(run.dataset, dir / "out", options);
  run.rows = read_estimates_csv(dir / "out" / "estimates.csv");
  return run;
}

}  // namespace pensight::testing
