// `pensight depth-data --out DIR --samples N --seed S`: training data for the depth network.
#include <CLI/CLI.hpp>
#include <string>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "core/log.h"
#include "sim/depth_training.h"

namespace pensight::app {

int cmd_depth_data(const Args& args) {
  CLI::App cli(
      "Renders random net-pen scenes (sim/depth_training.h), runs the FFT detector on each for its "
      "sparse depth priors and writes images, priors and ground-truth depth at the network's "
      "resolution into DIR, the input of scripts/train_depth.py. Sample i depends only on the "
      "seed and i. DIR is replaced if it holds earlier training data; nothing appears there "
      "unless every sample was written.",
      "pensight depth-data");
  sim::DepthDataOptions options;
  std::string out;
  bool quiet = false;
  cli.add_option("--out", out, "folder to write")->required();
  cli.add_option("--samples", options.samples, "number of random scenes")
      ->required()
      ->check(CLI::Range(1, 1000000));
  cli.add_option("--seed", options.seed, "seed of the scene draw")->capture_default_str();
  cli.add_option("--threads", options.threads, "worker threads (0: all cores)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cli.add_flag("--quiet", quiet, "no progress bar");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  ProgressBar bar("depth-data");
  if (!quiet) options.progress = [&](int done, int total) { bar.update(done, total); };
  sim::write_depth_data(out, options);
  if (!quiet) log_info("wrote " + out);
  return 0;
}

PENSIGHT_COMMAND("depth-data", "training data for the depth network (random rendered scenes)",
                 cmd_depth_data);

}  // namespace pensight::app
