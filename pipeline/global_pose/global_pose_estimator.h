#pragma once
// Fused global pose in the pen: an EKF (pen_ekf.h) over DVL velocity, attitude (roll and pitch
// level the sensors, yaw aids the heading through an estimated offset), pressure depth, the vision
// fixes (r_g, psi_r from the circle fit; d_net, psi_net from the FFT stage) and the DVL net plane.
// Every update is gated on its Mahalanobis distance, so a DVL spike or a bad vision frame is
// rejected and counted instead of moving the estimate. The horizontal process noise is quiet
// where the DVL shows quiet motion and an ROV's manoeuvring noise elsewhere (motion_schedule.h).
//
// Multi-rate input: samples may be added in any order. They wait in a time-ordered buffer and are
// applied in timestamp order when estimate(t) is asked for; other sensors' attitude is
// interpolated at each sample's timestamp. A sample older than what has been applied (late
// arrival) rolls the filter back to a snapshot before it and re-applies what followed, within
// `history_s`; older ones are dropped. Duplicates are dropped. All are counted, none is fatal.
//
// rho_g is 0 (or initial_rho_rad) at the first camera frame whose circle fit passes the lock rule
// (lock_rule.h), which also initialises the filter; before it r_g, rho_g and psi_g are NaN. Vision
// fixes that are gated out in a row yet agree with each other re-initialise the position. A value
// whose standard deviation exceeds its limit (e.g. rho_g with neither DVL nor attitude yaw) is
// reported as NaN.
#include <Eigen/Geometry>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/dataset_types.h"
#include "pipeline/global_pose/attitude_series.h"
#include "pipeline/global_pose/dvl_plane.h"
#include "pipeline/global_pose/dvl_spike_test.h"
#include "pipeline/global_pose/lock_rule.h"
#include "pipeline/global_pose/measurements.h"
#include "pipeline/global_pose/motion_schedule.h"
#include "pipeline/global_pose/pen_ekf.h"
#include "pipeline/global_pose/pen_fix.h"

namespace pensight::global_pose {

struct MeasurementNoise {
  double dvl_velocity_mps = 0.005;
  // Prior on the DVL's horizontal velocity error: a 1 % scale error at 0.3 m/s plus a few mm/s
  // of offset. A looser prior lets the bias states take up the vision's and the attitude's
  // noise and move the along-net position with it (docs/global_pose.md, 2026-12-02).
  double dvl_bias_prior_mps = 0.005;
  double depth_m = 0.02;
  double attitude_yaw_rad = 0.015;
  // Vision fix: the circle fit's covariance, floored and inflated (the ROI points' errors are
  // correlated through the FFT stage, which the fit's covariance does not know).
  double fix_r_floor_m = 0.01;
  double fix_psi_r_floor_rad = 0.005;
  double fix_inflation = 2.0;
  double d_net_frac = 0.03;  // relative to d_net
  double psi_net_rad = 0.035;
  double dvl_plane_distance_m = 0.03;
  double dvl_plane_heading_rad = 0.06;
  // Net texture odometry (net_texture.h): the odometer's reading against the along-wall
  // coordinate of the centre ray's net point, and the error each step adds to the odometer, a
  // constant part (the lattice phase's noise) and one in proportion to the step (the bars'
  // direction on the net).
  double net_texture_m = 0.001;
  double net_texture_step_m = 0.0005;
  double net_texture_step_frac = 0.01;
  // Whole bars are counted against a move predicted from the latest DVL velocity and the
  // attitude's yaw rate over this window (a line through its samples: 0.2 deg of noise at 20 Hz
  // leaves 1 mm at 1.3 m over a 0.1 s frame interval), and only where the measured move lies
  // within net_texture_max_unwrap_bars of it, modulo whole bars.
  double net_texture_yaw_rate_window_s = 0.5;
  double net_texture_max_unwrap_bars = 0.3;
  ProcessNoise process;
};

// Standard deviations of the states no measurement sets: at initialisation, at re-initialisation
// from agreeing fixes, and when a motion sensor re-locks (the states it measures are released).
// Each is wide against what it stands for, so the first measurement sets the state.
struct FilterPriors {
  double position_along_wall_m = 1e-4;  // rho_g is initial_rho_rad at the lock by definition
  double depth_without_pressure_m = 100;
  double velocity_without_dvl_mps = 0.5;
  double psi_rate_radps = 1.0;
  // The yaw rate at the lock from two attitude samples this far apart, with its sigma.
  double psi_rate_window_s = 0.1;
  double psi_rate_from_attitude_radps = 0.1;
  double attitude_yaw_offset_rad = 3.1622776601683795;  // any offset; the first sample sets it
  double velocity_after_reinit_mps = 0.3;               // the DVL sets it again
  // Released on a re-lock: above what a vehicle in a pen changes in one sample interval.
  double released_velocity_mps = 1.0;
  double released_heading_rad = 0.2;
  double released_psi_rate_radps = 1.0;
  double released_depth_m = 1.0;
};

struct GlobalPoseEstimatorConfig {
  double pen_radius_m = kDefaultPenRadius_m;  // scene.yaml; a flat net is a large radius (100 m)
  // scene.yaml net_type flat_panel: the wall is that plane instead of the pen_radius_m cylinder.
  std::optional<SceneConfig::FlatPanel> flat_panel;
  double initial_rho_rad = 0.0;
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();
  std::optional<DvlCalibration> dvl_beams;  // dvl0/sensor.yaml; no DVL plane updates without it
  // Which sensor folders the dataset has; an absent one is announced once, not an error.
  bool has_dvl = true;
  bool has_attitude = true;
  bool has_pressure = true;
  bool use_attitude_yaw = true;     // aid the heading with the attitude sensor's yaw
  bool use_vision_relative = true;  // fuse d_net / psi_net when given
  bool use_dvl_plane = true;
  bool use_net_texture = true;  // the net texture odometry of NetObservation::texture
  // radius_m is overwritten with pen_radius_m, or kFlatPanelFitRadius_m on a flat panel.
  CircleFitOptions circle;
  MeasurementNoise noise;
  FilterPriors priors;
  double gate_scale = 1.0;  // multiplies the chi-square gates (p = 0.999)
  // After this many rejections in a row a sensor's next sample is applied without the gate, so
  // the filter re-locks after a real jump instead of refusing it forever.
  int relock_after_rejections = 12;
  // DVL velocity, attitude yaw and pressure depth measure their states directly, and a manoeuvre
  // the constant-velocity model did not expect (a turn or a reversal), or a vertical velocity
  // guessed from the first few depth samples without a DVL, is gated out like a spike. A spike
  // lasts one or two samples; after this many rejections in a row the states they measure (u, v,
  // w; psi, psi_rate; z, w) are released to a wide prior and the sample is applied.
  int motion_relock_after_rejections = 2;
  // Which circle fits may initialise the filter, and when agreeing gated-out fixes re-initialise
  // its position (lock_rule.h).
  LockRule lock;
  // DVL velocity spikes: max_accel_mps2 and max_spike_samples (noise_mps is set from
  // noise.dvl_velocity_mps).
  DvlSpikeTestOptions dvl_spikes;
  double history_s = 2.0;
  double max_attitude_gap_s = 0.5;
  // Beyond these standard deviations a value is reported as NaN (not observable).
  double max_rho_sigma_rad = 0.2;
  // rho_g and psi_g are NaN when neither DVL velocity nor attitude yaw was applied this long.
  double max_unaided_s = 5.0;
  double max_z_sigma_m = 1.0;
};

// Throws pensight::Error "global pose: key 'PATH': VALUE is outside RANGE UNIT (HELP)" for the
// first value out of its range, nested parts under their member's name ("noise.process.yaw_accel");
// and "global pose: key 'flat_panel.plane_normal': ..." for a flat panel whose normal is not
// horizontal or points towards the pen frame's origin.
void validate(const GlobalPoseEstimatorConfig& config);
// Every numeric and bool key of GlobalPoseEstimatorConfig and its nested parts with its default,
// unit, valid range and help: the rows of a Markdown table under core/params.h's
// kParamTableHeader.
std::string global_pose_param_rows();

// A flat panel's net points are fitted as a circle of this radius: a line to within 0.05 mm over
// a 2 m view (sagitta w^2 / 8R), with the circle fit's robust machinery and covariance.
inline constexpr double kFlatPanelFitRadius_m = 1e4;

struct SensorCounters {
  int received = 0;
  int accepted = 0;
  int rejected = 0;      // failed the innovation gate, or a DVL spike
  int spikes = 0;        // DVL velocity only: beyond what the vehicle can do (dvl_spike_test.h)
  int relocked = 0;      // applied without the gate after relock_after_rejections
  int invalid = 0;       // NaN, invalid flag, failed fit
  int duplicates = 0;    // same sensor, same timestamp: dropped
  int out_of_order = 0;  // arrived after later samples were applied: re-applied in order
  int too_late = 0;      // older than history_s behind the filter: dropped
  // Vision fix only: fixes that failed the lock rule before initialisation, and re-lockings of
  // the position to agreeing gated-out fixes (LockRule).
  int not_lockable = 0;
  int reinitialised = 0;
};

struct GlobalPoseCounters {
  SensorCounters dvl_velocity, dvl_plane, depth, attitude, vision_fix, vision_relative, net_texture;
};

// One line per sensor, e.g. for the end-of-run report.
std::string describe(const GlobalPoseCounters& c);

class GlobalPoseEstimator {
 public:
  // Throws like validate().
  explicit GlobalPoseEstimator(GlobalPoseEstimatorConfig config);

  void add(const DvlSample& s);
  void add(const PressureSample& s);
  void add(const AttitudeSample& s);
  // Throws pensight::Error when obs.quality is neither empty nor one per point.
  void add(const NetObservation& obs);

  // Applies every buffered sample up to t_ns and returns the estimate at t_ns (one
  // estimates.csv row's r_g, rho_g, z_g, psi_g, with psi_r, the covariance and the body and
  // camera poses in P, measurements.h).
  GlobalPose estimate(int64_t t_ns);

  GlobalPoseCounters counters() const;
  bool initialised() const { return state_.initialised; }
  // The latest valid DVL net plane among the applied samples and its time; nullopt before one.
  std::optional<std::pair<int64_t, DvlPlane>> last_dvl_plane() const {
    if (state_.plane_ns == kNever) return std::nullopt;
    return std::make_pair(state_.plane_ns, state_.plane);
  }
  const GlobalPoseEstimatorConfig& config() const { return cfg_; }

 private:
  // Samples with the same timestamp are applied in this order (the buffer sorts by (t, kind)):
  // the attitude first, as it levels the others; pressure and DVL next, so that the camera frame
  // last meets the filter with every motion measurement of its instant.
  enum Kind : int { kAttitude = 0, kDepth = 1, kDvl = 2, kCamera = 3 };
  static constexpr int64_t kNever = std::numeric_limits<int64_t>::min();
  struct Event {
    int64_t t_ns = 0;
    Kind kind;
    std::variant<AttitudeSample, PressureSample, DvlSample, NetObservation> sample;
  };
  // Everything applying a sample changes, so a late sample can roll it back.
  struct FilterState {
    PenEkf ekf;
    bool initialised = false;
    bool yaw_bias_set = false;
    int64_t last_time_ns = kNever;
    int64_t last_rho_aid_ns = kNever;  // last accepted DVL velocity or attitude yaw
    int64_t init_ns = kNever;
    double last_depth_m = kNaN;
    Eigen::Vector3d last_velocity_L = Eigen::Vector3d::Constant(kNaN);
    GlobalPoseCounters counts;  // applied-sample counters
    std::array<int, 7> consecutive_rejections = {};
    // The latest valid DVL net plane, to check a fix against before it sets the position.
    int64_t plane_ns = kNever;
    DvlSample plane_sample;
    double plane_roll_rad = 0, plane_pitch_rad = 0;
    DvlPlane plane;
    // The current run of gated-out lockable vision fixes: time and (r, psi_r) innovation.
    struct RejectedFix {
      int64_t t_ns = 0;
      Eigen::Vector2d innovation;
    };
    std::vector<RejectedFix> rejected_fixes;
    // The net texture odometer (apply_texture): the frame it last read, its reading [m], the
    // filter's state, roll and pitch then, and its centre-ray net point in P with that point's
    // along-wall coordinate.
    struct TextureChain {
      bool active = false;
      int64_t last_ns = 0;
      double reading_m = 0;
      StateVector x = StateVector::Zero();
      double roll_rad = 0, pitch_rad = 0;
      Eigen::Vector3d hit_pen = Eigen::Vector3d::Zero();
      double hit_along_m = 0;
    };
    TextureChain texture;
  };
  struct Applied {
    Event event;
    FilterState before;
  };

  void enqueue(Event e, SensorCounters& arrival);
  // Rolls the filter back to before the latest applied sample, which waits to be applied again.
  void undo_last_applied();
  // The DVL velocity in P for the spike test and the motion schedule: levelled and turned by the
  // attitude (its yaw offset from P cancels in the difference of two samples), else by the
  // filter's heading.
  Eigen::Vector3d dvl_velocity_pen(const DvlSample& s) const;
  // The process noise from t0 to t1: quiet where the motion schedule says so.
  ProcessNoise process_noise(int64_t t0_ns, int64_t t1_ns) const;
  void apply(const Event& e);
  void apply_attitude(const AttitudeSample& s);
  void apply_depth(const PressureSample& s);
  void apply_dvl(const DvlSample& s);
  void apply_camera(const NetObservation& obs);
  // Net texture odometry: the odometer sums the centre ray's net point's moves over the net
  // (NetObservation::texture, whole bars resolved with the filter's predicted move) into an
  // along-wall reading; the filter measures reading = along(point) - net_texture_offset. The
  // point moves by r dpsi when the vehicle turns but by only d dpsi of the heading error, so the
  // heading's few tenths of a degree cost millimetres along the net, not the R dpsi of the
  // circle fit's azimuth. A step that does not follow the odometer's last frame, or a rejected
  // one, restarts it at the filter's point.
  void apply_texture(const NetObservation& obs, double roll, double pitch);
  // The filter's centre-ray net point in P for a camera ray, nullopt where it misses the wall.
  std::optional<Eigen::Vector3d> centre_ray_point(const StateVector& x,
                                                  const Eigen::Vector3d& ray_C, double roll,
                                                  double pitch) const;
  void start_texture_chain(const NetObservation& obs, double roll, double pitch);
  void initialise(const PenFix& fix, int64_t t_ns);
  // Releases the motion states a DVL velocity or attitude yaw measures (see
  // motion_relock_after_rejections).
  void release_motion_states(int sensor);
  // Counts a gated-out vision fix towards the re-initialisation rule (LockRule).
  void consider_reinitialising(const PenFix& fix, const Eigen::Vector2d& innovation, int64_t t_ns);
  // Re-locks x, y, psi to `fix` at the current azimuth after agreeing gated-out fixes, and
  // corrects the velocity by the rate at which their distance innovations grew.
  void reinitialise_position(const PenFix& fix, double distance_rate_mps, int64_t t_ns);
  // The vision fix as the wall model measures it: z = (distance to the wall, heading relative to
  // its outward normal), with the fit's covariance of z.
  struct WallFix {
    Eigen::Vector2d z;
    Eigen::Matrix2d covariance;
  };
  WallFix wall_fix(const PenFix& fix) const;
  // The pose a fix sets at azimuth rho_rad: the position, the wall's outward normal there and the
  // heading; nullopt where that azimuth's ray misses a flat panel.
  struct WallPose {
    Eigen::Vector2d xy_m;
    Eigen::Vector2d normal;
    double psi_rad = 0;
  };
  std::optional<WallPose> pose_from_fix(const WallFix& fix, double rho_rad) const;
  // check_lock plus the flat panel's reach and a recent DVL net plane, for the state the fix
  // would set at azimuth rho_rad.
  LockCheck check_lock_at(const PenFix& fix, double rho_rad, int64_t t_ns) const;
  // The DVL net plane (distance, heading) a pose would give with the beams of `s`.
  Eigen::Vector2d predicted_plane(const StateVector& x, const DvlSample& s, double roll,
                                  double pitch) const;
  // Roll and pitch at t (0 with a one-time warning when there is no attitude near t).
  std::pair<double, double> level_at(int64_t t_ns);
  template <int M, class H>
  UpdateOutcome gated_update(int sensor, SensorCounters& c, const Eigen::Matrix<double, M, 1>& z,
                             H&& h, const Eigen::Matrix<double, M, M>& R,
                             std::array<bool, M> angles, std::span<const int> depends_on);
  Eigen::Isometry3d T_pen_body(const StateVector& x, double roll, double pitch) const;
  void warn_once(int id, const std::string& message);

  GlobalPoseEstimatorConfig cfg_;
  NetWall wall_;
  FilterState state_;
  std::vector<Event> pending_;   // sorted by (t, kind)
  std::deque<Applied> history_;  // applied samples within history_s, oldest first
  bool history_trimmed_ = false;
  AttitudeSeries attitude_;
  DvlSpikeTest dvl_spikes_;     // on arrival: spikes never reach the buffer
  MotionSchedule motion_;       // quiet and manoeuvring spans, from the accepted DVL samples
  GlobalPoseCounters arrival_;  // duplicates, out_of_order, too_late, received
  std::array<bool, 16> warned_ = {};
};

}  // namespace pensight::global_pose
