// `pensight params`: every parameter a YAML file of pensight's takes, with its default, unit, valid
// range and meaning, from the one definition the readers use (core/params.h). docs/parameters.md
// is this output (`pensight params --write docs/parameters.md`); the test params.doc_is_current
// fails when it is not.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/command.h"
#include "control/control_config.h"
#include "core/atomic_file.h"
#include "core/file_bytes.h"
#include "core/params.h"
#include "live/record_config.h"
#include "pipeline/dataset/calibration_yaml.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/fft/net_detector_params.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"
#include "sim/scenario.h"
#include "vehicle/bluerov2_params.h"
#if PENSIGHT_HAS_MAPPING
#include "mapping/map_config.h"
#endif

namespace pensight::app {
namespace {

std::string parameters_markdown() {
  std::string doc =
      "# Parameters\n\n"
      "Every key of pensight's own YAML files with its default, unit, valid range and meaning, "
      "generated from the definitions the readers use (`pensight params --write "
      "docs/parameters.md`; `core/params.h`). An absent key keeps its default; an unknown key, a "
      "value of the wrong type or out of range is an error naming the file and the key.\n";
  doc += "\n## scene.yaml (`pipeline/dataset/calibration_yaml.h`; ../shared/dataset-format.md)\n\n";
  doc += std::string(kParamTableHeader) + scene_param_rows();
  doc += "\n## cam0/sensor.yaml\n\n" + std::string(kParamTableHeader) + camera_param_rows();
  doc += "\n## dvl0/sensor.yaml\n\n" + std::string(kParamTableHeader) + dvl_param_rows();
  doc +=
      "\nThe matrices, lists and names of these files (intrinsics, T_BS, beam_directions, "
      "net_mesh_type, net_type) are described in ../shared/dataset-format.md.\n";
  doc += "\n## Scenario (`pensight render SCENARIO`, `sim/scenario.h`)\n\n";
  doc += std::string(kParamTableHeader) + sim::scenario_param_rows();
  doc +=
      "\n## FFT net detector (`NetDetectorConfig`, `pipeline/fft/net_detector_params.h`; built "
      "in code, checked when the detector is made)\n\n";
  doc += std::string(kParamTableHeader) + net_detector_param_rows();
  doc += "\n## Dense depth (`DepthEstimatorConfig` and the DVL corrections)\n\n";
  doc += std::string(kParamTableHeader) + depth_param_rows();
  doc += "\n## Global pose (`GlobalPoseEstimatorConfig`)\n\n";
  doc += std::string(kParamTableHeader) + global_pose::global_pose_param_rows();
  doc += "\n## Published global-pose node (`PublishedGlobalPoseConfig`)\n\n";
  doc += std::string(kParamTableHeader) + global_pose::published_global_pose_param_rows();
  doc += "\n## Vehicle model (`vehicle/bluerov2_params.h`)\n\n";
  doc += std::string(kParamTableHeader) + vehicle::bluerov2_param_rows();
  doc +=
      "\n## Net-relative control (a scenario's `control:` section, `control/control_config.h`)\n\n";
  doc += std::string(kParamTableHeader) + control::control_param_rows();
  doc +=
      "\nA leg's `sway_speed_mps` is at most `limits.sway_speed_mps`, `safety.backoff_after_s` "
      "at least `safety.pose_timeout_s`, and `gains.surge_position.kp` and `gains.yaw.kp` are "
      "above 0.\n";
  doc +=
      "\n## Live session (`pensight record CONFIG`, `pensight sim-devices`, "
      "`live/record_config.h`; docs/vehicle.md)\n\n";
  doc += std::string(kParamTableHeader) + live::record_config_param_rows();
  doc +=
      "\nPaths are relative to the file's folder. Without `dvl:` no DVL is read, without "
      "`mavlink:` no depth or attitude.\n";
#if PENSIGHT_HAS_MAPPING
  doc += "\n## Occupancy map (`pensight map --config FILE`, `mapping/map_config.h`)\n\n";
  doc += std::string(kParamTableHeader) +
         param_table_rows<mapping::MapConfig>(mapping::map_params(), {});
  doc +=
      "\n`occupied_log_odds` is at most `max_log_odds`, and `max_range_m` at least a voxel "
      "beyond `min_range_m`.\n";
#endif
  return doc;
}

int cmd_params(const Args& args) {
  CLI::App cli("Prints every parameter of pensight's YAML files (docs/parameters.md)",
               "pensight params");
  std::string write, check;
  cli.add_option("--write", write, "write the Markdown to FILE instead of printing it");
  cli.add_option("--check", check, "exit 1 when FILE differs from what --write would write");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const std::string doc = parameters_markdown();
  if (!check.empty()) {
    if (!PENSIGHT_HAS_MAPPING) {
      std::printf("pensight params: built without the mapping layer; %s not checked\n",
                  check.c_str());
      return 0;
    }
    if (read_file_bytes(check).value_or("") != doc) {
      std::fprintf(stderr,
                   "pensight params: %s is not what the parameter definitions give; run "
                   "`pensight params --write %s`\n",
                   check.c_str(), check.c_str());
      return 1;
    }
    return 0;
  }
  if (!write.empty()) {
    write_file_atomically(write, doc);
    return 0;
  }
  std::fputs(doc.c_str(), stdout);
  return 0;
}

}  // namespace

PENSIGHT_COMMAND("params", "every parameter of pensight's YAML files, with defaults and ranges",
                 cmd_params);

}  // namespace pensight::app
