// `pensight bag-to-dataset BAG --out DIR --scene scene.yaml`: a ROS 1 bag converted to a dataset
// (docs/ros.md).
#include <CLI/CLI.hpp>
#include <string>

#include "apps/bag_input.h"
#include "apps/command.h"

namespace pensight::app {

int cmd_bag_to_dataset(const Args& args) {
  CLI::App cli(
      "Converts a ROS 1 bag (camera images and camera_info, DVL twist and ranges, pressure, IMU "
      "orientation) into DIR in the dataset layout of dataset-format.md; topics and frame "
      "conventions in docs/ros.md. DIR is replaced if it holds an earlier dataset; nothing "
      "appears there unless the whole bag converts.",
      "pensight bag-to-dataset");
  std::string bag, out;
  bool quiet = false;
  BagInputOptions options;
  cli.add_option("BAG", bag, "ROS 1 bag file")->required();
  cli.add_option("--out", out, "dataset folder to write")->required();
  add_bag_options(cli, options);
  cli.add_flag("--quiet", quiet, "no summary");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  convert_bag(bag, out, options, quiet);
  return 0;
}

PENSIGHT_COMMAND("bag-to-dataset", "convert a ROS 1 bag into a dataset (docs/ros.md)",
                 cmd_bag_to_dataset);

}  // namespace pensight::app
