#pragma once
// The net-relative controller (docs/control.md): the guidance legs, then the loops
//   x:   d_net - d_ref            -> u_ref (PID, published gains)
//   u:   u_ref - u_dvl            -> surge force around the feed-forward F(u_ref) (strategy a)
//   y:   along_ref - along        -> sway force around F(v_ref)                    (strategy a)
//        (along: the DVL's sway integrated; along_ref: the leg's speed integrated)
//   yaw: psi_net - heading_ref    -> yaw-rate demand
//   depth: depth_ref - depth      -> climb-rate demand (ArduSub's depth hold keeps it in between)
// turned into MANUAL_CONTROL sticks, and the safety logic around them:
//   startup: armed, depth hold for safety.startup_s, held still by the velocity loops (DVL) or on
//     neutral sticks;
//   no valid pose for pose_timeout_s: hold (DVL: zero speed; open loop: the surge thrust of the
//     last 2 s of tracking);
//   for backoff_after_s: back away from the net at backoff_speed_mps, up to backoff_max_m;
//   a valid pose again: tracking, the pose loops from rest (no derivative kick), the velocity
//     loops keeping their integrals (the current's force);
//   no DVL for dvl_timeout_s: the open-loop strategy until it is back.
// No clock and no I/O: samples and the time come in, sticks go out, so the same object runs on
// the vehicle and in the simulator.
#include <Eigen/Core>
#include <cstdint>

#include "control/control_config.h"
#include "control/guidance.h"
#include "core/units.h"

namespace pensight::control {

enum class ControlState { kStartup, kTracking, kHold, kBackOff };
const char* to_string(ControlState s);

struct ControlOutput {
  int64_t timestamp_ns = 0;
  ControlState state = ControlState::kStartup;
  VelocityStrategy strategy = VelocityStrategy::kDvlFeedback;  // in use now
  int leg = 0;
  double d_ref_m = kNaN, heading_ref_rad = kNaN, depth_ref_m = kNaN;
  double u_ref_mps = 0, v_ref_mps = 0, r_ref_radps = 0, climb_ref_mps = 0;
  double surge_force_n = 0, sway_force_n = 0;
  // MANUAL_CONTROL's sticks: x (forward), y (right), r (yaw right) in [-1, 1]; z in [0, 1], 0.5
  // holds the depth, above climbs.
  double x = 0, y = 0, z = 0.5, r = 0;
  bool arm = true, depth_hold = true;  // what the vehicle is asked to be in
};

struct ControlCounters {
  int steps = 0, hold_steps = 0, backoff_steps = 0, open_loop_fallback_steps = 0;
  int recoveries = 0;    // hold or back-off -> tracking
  int dvl_rejected = 0;  // samples dropped as spikes (SafetyConfig::dvl_gate_mps)
};

class NetController {
 public:
  // Throws pensight::Error (validate()) for a bad config.
  explicit NetController(ControlConfig config);

  // The relative pose of a frame and its quality (FftRelativePose::quality; 1 where none is
  // known); NaN d_net or psi_net: the frame had none. Within pose_timeout_s of the last pose, the
  // net estimate the loops act on moves pose_trust(quality) of the way to the pose
  // (core/pose_trust.h): a pose from a few ROIs, an oblique view or ROIs that disagree steers less
  // than one from the whole net.
  void on_pose(int64_t t_ns, double d_net_m, double psi_net_rad, double quality = 1.0);
  // The DVL's velocity in the body frame (FRD); a non-finite sample is ignored (a dropout), one
  // far from the observer's velocity dropped (a spike) unless the next agrees with it.
  void on_dvl(int64_t t_ns, const Eigen::Vector3d& velocity_body_mps);
  void on_depth(int64_t t_ns, double depth_m);

  // One control step at `now_ns` (the camera's rate is the design rate; any rate >= 5 Hz works).
  ControlOutput update(int64_t now_ns);
  const ControlCounters& counters() const { return counters_; }
  const ControlConfig& config() const { return config_; }

 private:
  // The velocity observer: the last DVL sample carried forward to now_ns with the force applied
  // since and the model's mass and damping.
  void propagate_velocity(int64_t now_ns);
  double feed_forward_surge(double u_mps) const;
  double feed_forward_sway(double v_mps) const;

  ControlConfig config_;
  LegTracker legs_;
  Pid x_, u_, y_, yaw_;
  ControlCounters counters_;
  ControlState state_ = ControlState::kStartup;
  VelocityStrategy strategy_in_use_;
  bool started_ = false;
  int64_t start_ns_ = 0, last_update_ns_ = 0;
  int64_t pose_ns_ = 0, dvl_ns_ = 0, depth_ns_ = 0;
  bool has_pose_ = false, has_dvl_ = false, has_depth_ = false;
  bool pose_fresh_ = false;
  double d_net_m_ = 0, psi_net_rad_ = 0, depth_m_ = 0;
  Eigen::Vector2d velocity_mps_ = Eigen::Vector2d::Zero();  // observer: surge, sway
  int64_t velocity_ns_ = 0;
  Eigen::Vector2d held_sample_mps_ = Eigen::Vector2d::Zero();  // a sample the gate held back
  bool holding_sample_ = false;
  double surge_force_n_ = 0, sway_force_n_ = 0;
  double tracking_force_n_ = 0;  // surge thrust while tracking, averaged over ~2 s
  // Along the net since the start (the observer's sway integrated) and where the legs want the
  // vehicle; the reference restarts from the vehicle after every state change.
  double along_m_ = 0, along_ref_m_ = 0;
  double backed_off_m_ = 0;
};

}  // namespace pensight::control
