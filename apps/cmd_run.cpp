#include <CLI/CLI.hpp>
#include <cstdio>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "pipeline/runner.h"

namespace pensight::app {

int cmd_run(const Args& args) {
  CLI::App cli(
      "Run the pipeline on a dataset (../shared/dataset-format.md layout) and write "
      "OUT/estimates.csv",
      "pensight run");
  std::string dataset_dir, out_dir, backend = "auto";
  bool quiet = false;
  cli.add_option("DATASET", dataset_dir, "dataset folder")->required();
  cli.add_option("--out", out_dir, "output folder")->required();
  cli.add_option("--backend", backend,
                 "auto|cpu|vulkan|cuda (auto: a real GPU, else the CPU path)");
  cli.add_flag("--quiet", quiet, "no progress bar");
  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    cli.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  RunOptions options;
  options.backend = parse_backend(backend);
  ProgressBar bar("run");
  if (!quiet) options.on_progress = [&](size_t done, size_t total) { bar.update(done, total); };
  const Dataset dataset = read_dataset(dataset_dir);
  const RunSummary s = run_dataset(dataset, out_dir, options);
  std::printf("backend: %s (%s; %s)\n", std::string(to_string(s.backend.backend)).c_str(),
              s.backend.device.c_str(), s.backend.reason.c_str());
  std::printf("frames: %zu (%zu skipped)\nstage times:\n%s", s.frames, s.frames_skipped,
              s.times.summary().c_str());
  std::printf("wrote %s/estimates.csv\n", out_dir.c_str());
  return 0;
}

PENSIGHT_COMMAND("run", "run the pipeline on a dataset and write OUT/estimates.csv", cmd_run);

}  // namespace pensight::app
