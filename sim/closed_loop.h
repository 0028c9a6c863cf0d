#pragma once
// `pensight closed-loop`: the scenario's world with the vehicle flown by its controller instead of
// along its waypoints. Each camera frame (in simulated time):
//   vehicle state -> render -> Pipeline (the vehicle's own perception: FFT detection, relative
//   pose, global pose) -> NetController (guidance, PIDs, safety) -> ArduSub-like autopilot ->
//   thrusters -> BlueROV2 Heavy dynamics in the current,
// with the DVL, pressure and attitude sampled from the simulated vehicle at their rates and fed to
// both the pipeline and the controller. The command of frame k acts perception_latency_s after
// the frame. docs/control.md.
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "control/net_controller.h"
#include "pipeline/fft/net_detector.h"
#include "runtime/device.h"
#include "sim/scenario.h"

namespace pensight::sim {

// One control step (one camera frame).
struct ClosedLoopStep {
  int64_t timestamp_ns = 0;
  double t_s = 0;
  // Truth: the camera's net-relative pose, where along the net the vehicle is (arc length of the
  // body's azimuth), its depth and body velocity over ground.
  double d_net_true_m = kNaN, psi_net_true_rad = kNaN;
  double along_true_m = 0, depth_true_m = 0;
  Eigen::Vector3d velocity_body_true_mps = Eigen::Vector3d::Zero();
  // Perception's relative pose (NaN: none, or withheld by an outage).
  double d_net_est_m = kNaN, psi_net_est_rad = kNaN;
  control::ControlOutput command;
};

struct ClosedLoopOptions {
  Backend renderer = Backend::kAuto;  // as `pensight render`
  NetDetectorConfig detector;         // the backend; the net's keys come from the scenario
  std::optional<control::VelocityStrategy> strategy;  // instead of the scenario's
  // [from, to) seconds after the start in which perception yields no pose, or the DVL nothing.
  std::vector<std::pair<double, double>> perception_outages_s, dvl_outages_s;
  // From the image to the command acting on the vehicle (detection and control on the vehicle).
  double perception_latency_s = 0.05;
  // Each step as it is taken, e.g. to send its command over MAVLink.
  std::function<void(const ClosedLoopStep&)> on_step;
  std::function<void(int steps_done, int steps_total)> progress;
};

struct ClosedLoopSummary {
  std::vector<ClosedLoopStep> steps;
  control::ControlCounters counters;
  double simulated_s = 0, wall_s = 0;
  // Where the wall time went: rendering, perception (push to result), writing the dataset, and
  // the rest (dynamics, sensors, control).
  double render_s = 0, perception_s = 0, write_s = 0;
  std::string renderer, backend;
};

// Runs the scenario (which needs a `control:` section) and writes `out`: the rendered dataset
// (cam0, groundtruth0 with depth, dvl0, pressure0, imu0; as `pensight render`),
// out/closed_loop.csv (contract 1.1) and out/closed_loop.html. Nothing appears under `out` unless
// the run completes. Throws pensight::Error for a scenario without control, a colour camera, or
// what Pipeline and the renderer throw.
ClosedLoopSummary run_closed_loop(const Scenario& s, const std::filesystem::path& out,
                                  const ClosedLoopOptions& options, Device& device);

}  // namespace pensight::sim
