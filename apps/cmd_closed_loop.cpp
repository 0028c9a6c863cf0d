// `pensight closed-loop SCENARIO.yaml --out OUT`: the vehicle flown by its controller in the
// synthetic world (sim/closed_loop.h), optionally sending its commands over MAVLink.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "apps/command.h"
#include "apps/progress_bar.h"
#include "core/log.h"
#include "mavlink/vehicle_link.h"
#include "sim/closed_loop.h"
#include "sim/closed_loop_report.h"
#include "sim/scenario.h"

namespace pensight::app {

int cmd_closed_loop(const Args& args) {
  CLI::App cli(
      "Flies the scenario's mission (its control: section) in closed loop: render, perception "
      "(the vehicle's pipeline), net-relative guidance and control, an ArduSub-like autopilot and "
      "the BlueROV2 Heavy's dynamics, in simulated time. Writes OUT as a dataset (cam0, "
      "groundtruth0, dvl0, pressure0, imu0) with OUT/closed_loop.csv and OUT/closed_loop.html.",
      "pensight closed-loop");
  std::string scenario_file, out, renderer = "auto", backend = "auto", strategy, mavlink_endpoint;
  double duration = -1;
  bool quiet = false;
  cli.add_option("SCENARIO", scenario_file, "scenario YAML with a control: section")->required();
  cli.add_option("--out", out, "output folder (a dataset, replaced if it holds one)")->required();
  cli.add_option("--strategy", strategy,
                 "dvl (velocity loops on the DVL) or open_loop (constant thrust per speed); "
                 "default: the scenario's")
      ->check(CLI::IsMember({"dvl", "open_loop"}));
  cli.add_option("--duration", duration, "fly only the first S seconds")
      ->check(CLI::Range(0.0, 21600.0));
  cli.add_option("--renderer", renderer, "auto, vulkan or cpu")->capture_default_str();
  cli.add_option("--backend", backend, "perception: auto|cpu|vulkan|cuda")->capture_default_str();
  cli.add_option("--mavlink", mavlink_endpoint,
                 "also send the commands over MAVLink v2 as a companion computer: "
                 "udpout:HOST:PORT (send to), udpin:ADDR:PORT (listen) or tcp:HOST:PORT "
                 "(connect to), as MAVProxy writes them");
  std::vector<double> outage;
  cli.add_option("--perception-outage", outage,
                 "FROM TO: seconds after the start between which perception yields no pose (a "
                 "test of the hold and back-off)")
      ->expected(2);
  cli.add_flag("--quiet", quiet, "no progress bar");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }

  sim::Scenario s = sim::load_scenario(scenario_file);
  if (duration >= 0) {
    s.duration_s = duration;
    sim::validate(s);
  }
  sim::ClosedLoopOptions options;
  options.renderer = parse_backend(renderer);
  options.detector.backend = parse_backend(backend);
  if (!outage.empty()) {
    if (!(outage[0] >= 0 && outage[1] > outage[0])) {
      std::fprintf(stderr, "pensight closed-loop: --perception-outage needs 0 <= FROM < TO\n");
      return 2;
    }
    options.perception_outages_s.emplace_back(outage[0], outage[1]);
  }
  if (!strategy.empty()) {
    options.strategy = strategy == "dvl" ? control::VelocityStrategy::kDvlFeedback
                                         : control::VelocityStrategy::kOpenLoop;
  }
  // The link runs on the simulation's clock: HEARTBEAT every simulated second, MANUAL_CONTROL
  // every step, arm and ALT_HOLD as the controller's start-up asks.
  std::optional<mavlink::VehicleLink> link;
  if (!mavlink_endpoint.empty()) {
    link.emplace(mavlink::LinkConfig{.endpoint = mavlink_endpoint,
                                     .role = mavlink::LinkRole::kCompanionComputer});
    options.on_step = [&link, armed = false](const sim::ClosedLoopStep& step) mutable {
      const control::ControlOutput& c = step.command;
      if (c.arm && !armed) {
        armed = link->arm(true) && link->set_mode(mavlink::SubMode::kAltHold);
      }
      link->set_manual_control(static_cast<int>(std::lround(1000 * c.x)),
                               static_cast<int>(std::lround(1000 * c.y)),
                               static_cast<int>(std::lround(1000 * c.z)),
                               static_cast<int>(std::lround(1000 * c.r)), step.timestamp_ns);
      link->poll(step.timestamp_ns);
    };
  }
  ProgressBar bar("closed loop");
  if (!quiet) options.progress = [&](int done, int total) { bar.update(done, total); };
  Device device;
  const sim::ClosedLoopSummary summary = sim::run_closed_loop(s, out, options, device);
  const sim::ClosedLoopMetrics m = sim::closed_loop_metrics(summary.steps);
  std::printf("closed loop '%s': %.1f s simulated in %.1f s (%.2fx real time)\n", s.name.c_str(),
              summary.simulated_s, summary.wall_s,
              summary.simulated_s / std::max(summary.wall_s, 1e-9));
  std::printf(
      "wall time: render %.1f s, dataset writing %.1f s, perception (beyond the writing) "
      "%.1f s, the rest %.1f s\n",
      summary.render_s, summary.write_s, summary.perception_s,
      summary.wall_s - summary.render_s - summary.write_s - summary.perception_s);
  std::printf("distance RMSE after settling %.1f cm, heading RMSE %.2f deg, nearest %.3f m\n",
              100 * m.distance_rmse_m, m.heading_rmse_deg, m.min_distance_m);
  for (const sim::LegMetrics& l : m.legs) {
    std::printf(
        "leg %d at %.1f s: d_ref %.2f m, step %+.2f m, settled after %.1f s, overshoot "
        "%.1f cm\n",
        l.leg, l.start_s, l.d_ref_m, l.step_m, l.settle_s, 100 * l.overshoot_m);
  }
  std::printf("hold / back-off / open-loop steps: %d / %d / %d; recoveries %d\n",
              summary.counters.hold_steps, summary.counters.backoff_steps,
              summary.counters.open_loop_fallback_steps, summary.counters.recoveries);
  if (link) {
    const mavlink::LinkCounters c = link->counters();
    std::printf("mavlink %s: %llu frames sent, %llu send errors, %llu received\n",
                mavlink_endpoint.c_str(), static_cast<unsigned long long>(c.frames_sent),
                static_cast<unsigned long long>(c.send_errors),
                static_cast<unsigned long long>(c.parse.frames));
  }
  if (!quiet) log_info("wrote " + out + " (closed_loop.csv, closed_loop.html)");
  return 0;
}

PENSIGHT_COMMAND("closed-loop", "fly a scenario's mission in closed loop (scenarios/hold_0p5.yaml)",
                 cmd_closed_loop);

}  // namespace pensight::app
