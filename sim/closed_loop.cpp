#include "sim/closed_loop.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

#include "core/error.h"
#include "core/units.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"
#include "pipeline/pipeline.h"
#include "sim/closed_loop_report.h"
#include "sim/generate.h"
#include "sim/ground_truth.h"
#include "sim/net_geometry.h"
#include "sim/sensors.h"
#include "tools/runner.h"
#include "vehicle/vehicle_sim.h"

namespace pensight::sim {
namespace {

bool inside(const std::vector<std::pair<double, double>>& windows, double t_s) {
  for (const auto& [from, to] : windows) {
    if (t_s >= from && t_s < to) return true;
  }
  return false;
}

BodyState body_of(const vehicle::VehicleSim& v) {
  BodyState b;
  b.T_pen_body.linear() = v.R_pen_body();
  b.T_pen_body.translation() = v.position_pen_m();
  const Eigen::Vector3d rpy = v.rpy_rad();
  b.roll_rad = rpy[0];
  b.pitch_rad = rpy[1];
  b.yaw_rad = rpy[2];
  b.velocity_pen_mps = v.velocity_pen_mps();
  b.angular_velocity_body_radps = v.angular_velocity_body_radps();
  return b;
}

// Arc length along the net of the body's azimuth (cylinder), or its position along the panel.
double along_net_m(const PenConfig& pen, const Eigen::Vector3d& p_pen_m) {
  if (pen.shape == NetShape::kPlane) return p_pen_m.y();
  return pen.radius_m * std::atan2(p_pen_m.y(), p_pen_m.x());
}

// A sensor sampled every 1 / rate_hz from the start.
struct Schedule {
  double period_s, next_s = 0;
  bool due(double t_s) {
    if (t_s + 1e-9 < next_s) return false;
    next_s += period_s;
    return true;
  }
};

}  // namespace

ClosedLoopSummary run_closed_loop(const Scenario& s, const std::filesystem::path& out,
                                  const ClosedLoopOptions& options, Device& device) {
  if (!s.control) {
    throw Error(s.file.string() +
                ": no 'control:' section; a closed loop needs its mission and controller "
                "(see scenarios/hold_0p5.yaml)");
  }
  if (s.camera.colour) {
    throw Error(s.file.string() + ": key 'camera.colour': the closed loop renders grey frames");
  }
  const auto wall_start = std::chrono::steady_clock::now();
  control::ControlConfig control_config = *s.control;
  if (options.strategy) control_config.strategy = *options.strategy;
  control::NetController controller(control_config);

  // The vehicle starts at the trajectory's first pose, at rest.
  const BodyState start = body_state(s, 0);
  vehicle::RigidBodyState initial;
  initial.position_pen_m = start.T_pen_body.translation();
  initial.q_pen_body = Eigen::Quaterniond(start.T_pen_body.linear());
  vehicle::VehicleSim vehicle(s.vehicle, initial);

  const NetGeometry net(s.pen, s.net);
  const auto renderer = make_renderer(s, RenderOptions{}, options.renderer, device);

  const DatasetContents contents = dataset_contents(s);
  PipelineConfig config;
  config.camera = contents.cam0.camera;
  config.detector = detector_config(contents.scene, options.detector);
  config.global_pose = global_pose_config(contents.scene, contents.cam0, contents.dvl0,
                                          contents.pressure0, contents.imu0);
  Pipeline pipeline(config, device);

  DatasetWriter writer(out, contents);

  std::mt19937_64 dvl_rng(s.seed * 7 + 1), pressure_rng(s.seed * 7 + 2),
      attitude_rng(s.seed * 7 + 3);
  const double camera_period_s = 1.0 / s.camera.calibration.rate_hz;
  Schedule dvl{1.0 / s.dvl.rate_hz}, pressure{1.0 / s.pressure.rate_hz},
      attitude{1.0 / s.attitude.rate_hz};
  const auto ns_at = [&](double t_s) { return s.start_time_ns + seconds_to_ns(t_s); };

  ClosedLoopSummary summary;
  summary.renderer = renderer->name();
  summary.backend = pipeline.backend_description();
  const int frames = s.num_frames();
  // The physics ticks at 200 Hz between events; sensors fire on the first tick at or after
  // their time.
  constexpr double kTick_s = 0.005;
  // The latest command and when it lands (infinity: landed).
  vehicle::ManualCommand pending;
  double pending_at_s = std::numeric_limits<double>::infinity();
  for (int k = 0; k < frames; ++k) {
    const double t_frame = k * camera_period_s;
    // Up to the frame: the vehicle moves, the sensors sample it, a pending command lands.
    while (true) {
      const double t = vehicle.time_s();
      if (t + 1e-9 >= pending_at_s) {
        vehicle.set_command(pending);
        pending_at_s = std::numeric_limits<double>::infinity();
      }
      const BodyState b = body_of(vehicle);
      const int64_t ns = ns_at(t);
      if (s.dvl.enabled && dvl.due(t)) {
        DvlSample d = measure_dvl(s.dvl, net, b, ns, dvl_rng);
        if (inside(options.dvl_outages_s, t)) {
          d.valid = false;
          d.velocity_B_mps.setConstant(kNaN);
        }
        writer.add_dvl(d);
        pipeline.push(d);
        if (d.valid) controller.on_dvl(ns, d.velocity_B_mps);
      }
      if (s.pressure.enabled && pressure.due(t)) {
        const PressureSample p = measure_pressure(s.pressure, b, ns, pressure_rng);
        writer.add_pressure(p);
        pipeline.push(p);
        controller.on_depth(ns, p.depth_m);
      }
      if (s.attitude.enabled && attitude.due(t)) {
        const AttitudeSample a = measure_attitude(s.attitude, b, ns, attitude_rng);
        writer.add_attitude(a);
        pipeline.push(a);
      }
      if (t + 1e-9 >= t_frame) break;
      vehicle.advance(std::min(kTick_s, t_frame - t));
    }

    // The frame: rendered, perceived, controlled.
    const double t = vehicle.time_s();
    const FrameState f = frame_state_at(s, body_of(vehicle), k, t);
    auto tic = std::chrono::steady_clock::now();
    const auto toc = [&tic](double& total_s) {
      const auto now = std::chrono::steady_clock::now();
      total_s += std::chrono::duration<double>(now - tic).count();
      tic = now;
    };
    const RenderedFrame r = renderer->render(f);
    toc(summary.render_s);
    pipeline.push(CameraFrame{f.timestamp_ns, r.image, nullptr});
    // The dataset is written while perception runs on the pipeline's threads.
    const GroundTruthRow truth =
        ground_truth_row(s.net_changes.empty() ? s : s.with_net_at(f.t_s), net, f, r.depth_m);
    writer.add_frame(f.timestamp_ns, r.image);
    writer.add_groundtruth(truth, depth_mm_from_m(r.depth_m));
    toc(summary.write_s);
    std::optional<FrameResult> result;
    while (!(result = pipeline.poll())) std::this_thread::sleep_for(std::chrono::microseconds(100));
    toc(summary.perception_s);

    ClosedLoopStep step;
    step.timestamp_ns = f.timestamp_ns;
    step.t_s = t;
    step.d_net_true_m = truth.d_net_m;
    step.psi_net_true_rad = truth.psi_net_rad;
    step.along_true_m = along_net_m(s.pen, vehicle.position_pen_m());
    step.depth_true_m = vehicle.depth_m();
    step.velocity_body_true_mps = vehicle.velocity_body_mps();
    const FftRelativePose& pose = result->detection.pose;
    if (pose.valid() && !inside(options.perception_outages_s, t)) {
      step.d_net_est_m = pose.d_net_m;
      step.psi_net_est_rad = pose.psi_net_rad;
    }
    controller.on_pose(f.timestamp_ns, step.d_net_est_m, step.psi_net_est_rad, pose.quality);
    step.command = controller.update(f.timestamp_ns);
    vehicle::ManualCommand command;
    command.x = step.command.x;
    command.y = step.command.y;
    command.z = step.command.z;
    command.r = step.command.r;
    command.armed = step.command.arm;
    command.mode =
        step.command.depth_hold ? vehicle::FlightMode::kAltHold : vehicle::FlightMode::kStabilize;
    pending = command;
    pending_at_s = t + options.perception_latency_s;
    if (options.on_step) options.on_step(step);
    summary.steps.push_back(step);
    if (options.progress) options.progress(k + 1, frames);
  }
  pipeline.finish();
  writer.finish();
  summary.counters = controller.counters();
  summary.simulated_s = vehicle.time_s();
  summary.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  write_closed_loop_csv(out / "closed_loop.csv", summary.steps);
  write_closed_loop_html(out / "closed_loop.html", s, summary);
  return summary;
}

}  // namespace pensight::sim
