// `pensight record CONFIG.yaml --out DIR [--duration S]`: the live sources a CONFIG names
// (live/record_config.h, docs/vehicle.md) recorded into a dataset that `pensight run` replays.
// Ctrl-C (SIGINT) or SIGTERM ends the recording cleanly; a harder kill leaves the dataset readable
// up to its last complete row.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

#include "apps/command.h"
#include "apps/stop_signal.h"
#include "live/record_config.h"
#include "live/recorder.h"

namespace pensight::app {
int cmd_record(const Args& args) {
  CLI::App cli("Record the live camera, DVL and autopilot a CONFIG names into a dataset",
               "pensight record");
  std::string config_file, out_dir;
  double duration_s = std::numeric_limits<double>::infinity();
  cli.add_option("CONFIG", config_file, "the live session's YAML (docs/vehicle.md)")->required();
  cli.add_option("--out", out_dir, "dataset folder to create (absent or empty)")->required();
  cli.add_option("--duration", duration_s, "seconds to record (default: until Ctrl-C)")
      ->check(CLI::PositiveNumber);
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const live::RecordConfig config = live::read_record_config(config_file);
  live::Recorder recorder(config, out_dir);
  std::printf("recording %s into %s%s\n", config.camera.uri.text.c_str(), out_dir.c_str(),
              std::isinf(duration_s) ? " until Ctrl-C" : "");
  std::fflush(stdout);
  recorder.run(duration_s, stop_on_signals());
  std::printf("%s", recorder.summary_text().c_str());
  return 0;
}

PENSIGHT_COMMAND("record", "record live sensors (camera, DVL, ArduSub) into a dataset", cmd_record);

}  // namespace pensight::app
