// `pensight render SCENARIO.yaml --out DIR`: renders a synthetic sequence into a dataset.
#include <CLI/CLI.hpp>
#include <string>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "core/log.h"
#include "sim/generate.h"
#include "sim/scenario.h"

namespace pensight::app {

int cmd_render(const Args& args) {
  CLI::App cli(
      "Renders the scenario into DIR in the dataset layout of dataset-format.md (cam0, dvl0, "
      "pressure0, imu0, groundtruth0 with depth). The result is the same for the same scenario, "
      "seed and renderer. DIR is replaced if it holds an earlier dataset; nothing appears there "
      "unless the run completes.",
      "pensight render");
  std::string scenario_file, out, renderer_name = "auto";
  int frames = 0;
  double duration = -1;
  bool quiet = false;
  sim::RenderOptions options;
  cli.add_option("SCENARIO", scenario_file, "scenario YAML (scenarios/*.yaml)")->required();
  cli.add_option("--out", out, "dataset folder to write")->required();
  cli.add_option("--frames", frames, "render only the first N camera frames")
      ->check(CLI::Range(1, 10000000));
  cli.add_option("--duration", duration, "render only the first S seconds")
      ->check(CLI::Range(0.0, 1e7));
  cli.add_option("--renderer", renderer_name,
                 "auto (vulkan where a device opens, lavapipe included; else the CPU reference), "
                 "vulkan or cpu")
      ->capture_default_str();
  cli.add_flag("!--no-noise", options.noise, "no sensor noise in the images");
  cli.add_flag("--quiet", quiet, "no progress bar");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  sim::Scenario s = sim::load_scenario(scenario_file);
  if (duration >= 0) s.duration_s = duration;
  if (frames > 0) s.duration_s = (frames - 1) / s.camera.calibration.rate_hz;
  if (duration >= 0 || frames > 0) sim::validate(s);

  Device device;
  const auto renderer = sim::make_renderer(s, options, parse_backend(renderer_name), device);
  ProgressBar bar("render");
  sim::GenerateOptions gen;
  if (!quiet) {
    log_info("rendering " + std::to_string(s.num_frames()) + " frames of '" + s.name + "' with " +
             renderer->name());
    gen.progress = [&](int done, int total) { bar.update(done, total); };
  }
  sim::generate_dataset(s, *renderer, out, gen);
  if (!quiet) log_info("wrote " + out);
  return 0;
}

PENSIGHT_COMMAND("render", "render a scenario (scenarios/*.yaml) into a synthetic dataset",
                 cmd_render);

}  // namespace pensight::app
