// The README's main command: renders the built-in default scenario (the paper-style sweep,
// scenarios/sweep.yaml compiled in) into a temporary dataset, runs the pipeline on it, and prints
// per-stage timing and the accuracy against the ground truth.
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "core/timing.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "sim/generate.h"
#include "sim/scenario.h"
#include "tools/evaluation/evaluation.h"
#include "tools/runner.h"

namespace pensight::app {

extern const char kBuiltinSweepYaml[];  // generated from scenarios/sweep.yaml

namespace {

// Removes the demo's temporary folder however the command ends.
struct TempDir {
  std::filesystem::path path;
  bool keep = false;
  ~TempDir() {
    std::error_code ec;
    if (!keep) std::filesystem::remove_all(path, ec);
  }
};

}  // namespace

int cmd_demo(const Args& args) {
  CLI::App cli(
      "Render the built-in sweep scenario, run the pipeline on it and score it against the "
      "ground truth",
      "pensight demo");
  std::string backend = "auto", renderer = "auto", keep;
  cli.add_option("--backend", backend, "pipeline backend: auto|cpu|vulkan|cuda")
      ->capture_default_str();
  cli.add_option("--renderer", renderer, "auto|cpu|vulkan")->capture_default_str();
  cli.add_option("--keep", keep, "keep the rendered dataset and estimates in this folder");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  TempDir dir{keep.empty() ? std::filesystem::temp_directory_path() /
                                 ("pensight-demo-" + std::to_string(::getpid()))
                           : std::filesystem::path(keep),
              !keep.empty()};
  const std::filesystem::path dataset_dir = dir.path / "sweep", out_dir = dir.path / "out";
  std::filesystem::create_directories(dir.path);

  const sim::Scenario scenario = sim::parse_scenario(kBuiltinSweepYaml, "sweep.yaml");
  Device device;
  const auto frame_renderer = sim::make_renderer(scenario, {}, parse_backend(renderer), device);
  std::printf("1. rendering the built-in sweep (%d frames of 720x540, %s renderer)\n",
              scenario.num_frames(), frame_renderer->name());
  std::fflush(stdout);  // before the progress bar on stderr
  ProgressBar render_bar("render");
  Stopwatch render_clock;
  sim::generate_dataset(scenario, *frame_renderer, dataset_dir,
                        {[&](int done, int total) { render_bar.update(done, total); }});
  const double render_s = render_clock.elapsed_ms() / 1e3;

  RunOptions options;
  options.detector.backend = parse_backend(backend);
  ProgressBar run_bar("run");
  options.on_progress = [&](size_t done, size_t total) { run_bar.update(done, total); };
  const Dataset dataset = read_dataset(dataset_dir);
  std::printf("2. running the pipeline\n");
  std::fflush(stdout);
  const RunSummary s = run_dataset(dataset, out_dir, options, device);
  std::printf("   backend: %s\n   frames: %zu (%zu without a net pose)\n   timing per node:\n%s",
              s.backend.c_str(), s.frames, s.frames_without_pose,
              format_timing_table(s.timing).c_str());

  const auto rows = read_estimates_csv(out_dir / "estimates.csv");
  std::printf(
      "3. accuracy against ground truth (measurable: net fills >= half the image, "
      "0.4-2.5 m, |psi_net| <= 35 deg)\n   net pose from FFT:\n%s"
      "   global pose (all frames; rho_g and psi_g as changes from the first frame with both):\n%s",
      describe(score_net_pose(dataset, rows, NetPoseSource::kFft)).c_str(),
      describe(score_global_pose(dataset, rows)).c_str());
  std::printf(
      "   global pose of the published node (the baseline, same frames):\n%s",
      describe(score_global_pose(dataset, read_global_pose_csv(out_dir / kPublishedGlobalPoseFile)))
          .c_str());
  std::printf("rendering took %.1f s%s\n", render_s,
              keep.empty() ? ""
                           : ("; dataset and estimates kept in " + keep + " (open " +
                              (out_dir / "report.html").string() + ")")
                                 .c_str());
  return 0;
}

PENSIGHT_COMMAND("demo", "render the built-in sweep, run the pipeline, print timing and accuracy",
                 cmd_demo);

}  // namespace pensight::app
