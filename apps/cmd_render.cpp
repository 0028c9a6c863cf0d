// `pensight render SCENARIO.yaml --out DIR`: renders a synthetic sequence into a dataset.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "apps/command.h"
#include "runtime/error.h"
#include "runtime/log.h"
#include "runtime/timing.h"
#include "sim/generate.h"
#include "sim/scenario.h"

namespace pensight::app {
namespace {

const char* kUsage = R"(usage: pensight render SCENARIO.yaml --out DIR [options]

Renders the scenario into DIR in the dataset layout of dataset-format.md (cam0, dvl0, pressure0,
imu0, groundtruth0 with depth). The result is the same for the same scenario, seed and renderer.
DIR is replaced if it holds an earlier dataset; nothing appears there unless the run completes.

options:
  --frames N          render only the first N camera frames
  --duration S        render only the first S seconds
  --renderer R        auto (default: vulkan where a device exists, else cpu), vulkan or cpu
  --no-noise          no sensor noise in the images
  --quiet             no progress bar
)";

double parse_number(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw Error(flag + ": expected a number, got '" + text + "'");
  return v;
}

void progress_bar(int done, int total, double elapsed_s) {
  constexpr int kWidth = 40;
  const int filled = total > 0 ? done * kWidth / total : kWidth;
  std::fprintf(stderr, "\r[%s%s] %d/%d frames, %.1f s", std::string(filled, '#').c_str(),
               std::string(kWidth - filled, '.').c_str(), done, total, elapsed_s);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace

int cmd_render(const Args& args) {
  std::string scenario_file, out, renderer_name = "auto";
  double frames = -1, duration = -1;
  bool quiet = false;
  sim::RenderOptions options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw Error(a + " needs a value (see pensight render --help)");
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::printf("%s", kUsage);
      return 0;
    } else if (a == "--out") {
      out = value();
    } else if (a == "--frames") {
      frames = parse_number(a, value());
      if (frames < 1 || frames != static_cast<int>(frames)) throw Error("--frames: must be >= 1");
    } else if (a == "--duration") {
      duration = parse_number(a, value());
      if (duration < 0) throw Error("--duration: must not be negative");
    } else if (a == "--renderer") {
      renderer_name = value();
    } else if (a == "--no-noise") {
      options.noise = false;
    } else if (a == "--quiet") {
      quiet = true;
    } else if (a.starts_with("-")) {
      throw Error("unknown option '" + a + "' (see pensight render --help)");
    } else if (scenario_file.empty()) {
      scenario_file = a;
    } else {
      throw Error("more than one scenario given ('" + scenario_file + "', '" + a + "')");
    }
  }
  if (scenario_file.empty() || out.empty()) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  sim::Scenario s = sim::load_scenario(scenario_file);
  if (duration >= 0) s.duration_s = duration;
  if (frames > 0) s.duration_s = (frames - 1) / s.camera.calibration.rate_hz;
  if (duration >= 0 || frames > 0) sim::validate(s);

  const auto renderer = sim::make_renderer(s, options, renderer_name);
  const Stopwatch clock;
  sim::GenerateOptions gen;
  if (!quiet) {
    log_info("rendering " + std::to_string(s.num_frames()) + " frames of '" + s.name + "' with " +
             renderer->name());
    gen.progress = [&](int done, int total) { progress_bar(done, total, clock.elapsed_ms() / 1e3); };
  }
  sim::generate_dataset(s, *renderer, out, gen);
  if (!quiet) log_info("wrote " + out);
  return 0;
}

PENSIGHT_COMMAND("render", "render a scenario (scenarios/*.yaml) into a synthetic dataset",
                 cmd_render);

}  // namespace pensight::app
