// `pensight sim-devices DATASET --config CONFIG.yaml`: a dataset served by stand-ins for the
// camera, a Water Linked DVL or a Nucleus's data port, and ArduSub at the addresses CONFIG names
// (live/device_standins.h), in real time, so that `pensight record CONFIG.yaml` beside it runs
// without the hardware.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "apps/command.h"
#include "apps/stop_signal.h"
#include "live/device_standins.h"
#include "live/record_config.h"

namespace pensight::app {
int cmd_sim_devices(const Args& args) {
  CLI::App cli(
      "Serve a dataset as live devices (camera stream, Water Linked DVL or Nucleus, ArduSub) on "
      "the "
      "addresses a record CONFIG names",
      "pensight sim-devices");
  std::string dataset_dir, config_file;
  live::StandInParams p;
  cli.add_option("DATASET", dataset_dir, "dataset folder to serve")->required();
  cli.add_option("--config", config_file, "the record YAML whose addresses to serve on")
      ->required();
  cli.add_option("--dvl-clock-offset", p.dvl_clock_offset_s, "the DVL's clock minus the host's, s")
      ->capture_default_str();
  cli.add_option("--dvl-delay", p.dvl_delay_s,
                 "ping's time of validity to its report leaving the DVL, s")
      ->capture_default_str();
  cli.add_option("--lead-in", p.lead_in_s, "seconds the devices wait for clients before playing")
      ->capture_default_str();
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const Dataset dataset = read_dataset(dataset_dir);
  const live::RecordConfig config = live::read_record_config(config_file);
  live::DeviceStandIns standins(dataset, config, p);
  std::printf("serving %s at the addresses of %s\n", dataset_dir.c_str(), config_file.c_str());
  std::fflush(stdout);
  standins.run(stop_on_signals());
  const live::StandInCounters c = standins.counters();
  std::printf(
      "served %llu frames, %llu DVL reports, %llu attitudes, %llu pressures\n",
      static_cast<unsigned long long>(c.frames), static_cast<unsigned long long>(c.dvl_reports),
      static_cast<unsigned long long>(c.attitudes), static_cast<unsigned long long>(c.pressures));
  return 0;
}

PENSIGHT_COMMAND("sim-devices", "serve a dataset as live devices for pensight record",
                 cmd_sim_devices);

}  // namespace pensight::app
