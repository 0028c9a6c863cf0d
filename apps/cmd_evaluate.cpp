#include <CLI/CLI.hpp>
#include <cstdio>

#include "apps/command.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "tools/evaluation/evaluation.h"

namespace pensight::app {

int cmd_evaluate(const Args& args) {
  CLI::App cli(
      "Score OUT/estimates.csv (and OUT/global_pose_published.csv if present) against the "
      "dataset's groundtruth0",
      "pensight evaluate");
  std::string dataset_dir, out_dir;
  AccuracyEnvelope envelope;
  cli.add_option("DATASET", dataset_dir, "dataset folder with groundtruth0/")->required();
  cli.add_option("OUT", out_dir, "folder holding estimates.csv (pensight run --out)")->required();
  cli.add_option("--min-net-fraction", envelope.min_net_fraction,
                 "measurable frames: share of pixels that see net")
      ->capture_default_str();
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const Dataset dataset = read_dataset(dataset_dir);
  const auto rows = read_estimates_csv(std::filesystem::path(out_dir) / "estimates.csv");
  const std::filesystem::path published_file =
      std::filesystem::path(out_dir) / kPublishedGlobalPoseFile;
  std::printf(
      "measurable: net fraction >= %.2f, %.1f-%.1f m, |psi_net| <= 35 deg\n"
      "net pose from FFT:\n%s"
      "global pose (all frames; rho_g and psi_g as changes from the first frame with both):\n%s",
      envelope.min_net_fraction, envelope.min_d_net_m, envelope.max_d_net_m,
      describe(score_net_pose(dataset, rows, NetPoseSource::kFft, envelope)).c_str(),
      describe(score_global_pose(dataset, rows)).c_str());
  if (std::filesystem::exists(published_file)) {
    std::printf("global pose of the published node (%s, the baseline):\n%s",
                kPublishedGlobalPoseFile,
                describe(score_global_pose(dataset, read_global_pose_csv(published_file))).c_str());
  }
  return 0;
}

PENSIGHT_COMMAND("evaluate", "score OUT/estimates.csv against the dataset's ground truth",
                 cmd_evaluate);

}  // namespace pensight::app
