#pragma once
// Geometric ground truth for the global-pose tests: a vehicle moving along the wall of a vertical
// cylindrical pen (z down), the net points a camera at T_body_camera would get from the 5x6 FFT
// ROI grid (rays through the ROI centres meeting the cylinder, with range noise and outliers), and
// DVL, pressure and attitude streams with the usual error models.
#include <Eigen/Geometry>
#include <functional>
#include <random>
#include <vector>

#include "core/camera.h"
#include "core/dataset_types.h"
#include "pipeline/global_pose/dvl_plane.h"
#include "pipeline/global_pose/measurements.h"

namespace pensight::global_pose::sim {

struct Pose {
  double t_s = 0;
  Eigen::Vector3d p_pen = Eigen::Vector3d::Zero();
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;

  Eigen::Isometry3d T_pen_body() const;
  double r_m() const { return p_pen.head<2>().norm(); }
  double rho_rad() const { return std::atan2(p_pen.y(), p_pen.x()); }
  double psi_r_rad() const { return wrap_angle(yaw_rad - rho_rad()); }
};

// Forward-looking camera 0.3 m ahead of and 0.1 m below the body origin.
Eigen::Isometry3d forward_camera();
// Forward-looking DVL 0.4 m ahead, 0.2 m below, four beams 22.5 deg off its boresight (+z_S).
DvlCalibration forward_dvl();

struct PointNoise {
  double range_sigma_frac = 0.015;  // FFT depth noise, relative to range
  double outlier_fraction = 0.1;
  double outlier_sigma_m = 0.5;
  double max_range_m = 6.0;  // farther ROIs find no net (NaN point)
  double d_net_sigma_frac = 0.02;
  double psi_net_sigma_rad = 0.02;
};

// One camera frame: ROI-centre net points in C.
NetObservation net_observation(const Pose& pose, double radius_m,
                               const Eigen::Isometry3d& T_body_camera, const PointNoise& noise,
                               std::mt19937_64& rng, const PinholeCamera& camera = {});

struct Trajectory {
  double radius_m = kDefaultPenRadius_m;
  double duration_s = 120.0;
  double speed_mps = 0.3;         // along the net
  double mean_distance_m = 1.35;  // body origin to net
  double distance_amp_m = 0.55;
  double psi_r_amp_rad = 0.2;
  double depth_m = 5.0;
  double depth_amp_m = 1.0;
  double roll_pitch_amp_rad = 0.0;

  Pose at(double t_s) const;
  Eigen::Vector3d body_velocity(double t_s) const;  // of the body origin, in B
};

struct SensorNoise {
  double dvl_sigma_mps = 0.01;
  double dvl_scale_error = 0.01;  // 1 % scale factor (sound speed, misalignment)
  Eigen::Vector3d dvl_bias_mps = {0.004, 0.004, 0.0};
  double dvl_range_sigma_m = 0.02;
  double depth_sigma_m = 0.02;
  double attitude_sigma_rad = 0.003;
  double yaw_sigma_rad = 0.01;
  double yaw_offset_rad = 0.7;       // AHRS yaw origin differs from the pen frame
  double yaw_drift_radps = 4.85e-6;  // 1 deg/h
  PointNoise points;
};

struct Sequence {
  std::vector<DvlSample> dvl;
  std::vector<PressureSample> depth;
  std::vector<AttitudeSample> attitude;
  std::vector<NetObservation> camera;
  std::vector<Pose> truth;  // one per camera frame
};

inline constexpr int64_t kStart_ns = 1'700'000'000'000'000'000;

// Camera 10 Hz, DVL 4 Hz, pressure 8 Hz, attitude 20 Hz, on staggered clocks.
Sequence make_sequence(const Trajectory& traj, const SensorNoise& noise, uint64_t seed,
                       const Eigen::Isometry3d& T_body_camera = forward_camera(),
                       const DvlCalibration& dvl = forward_dvl());

// Fills every camera frame's texture step but the first (net_texture.h): the optical axis' net
// point's true move over a square mesh of bar_length_m (horizontal and vertical bars) since the
// previous frame, in bars with white noise of sigma_bars, wrapped to [-0.5, 0.5).
void add_texture_steps(Sequence& seq, double radius_m, const Eigen::Isometry3d& T_body_camera,
                       double bar_length_m, double sigma_bars, std::mt19937_64& rng);

// Calls the visitor with every sample of the sequence in timestamp order.
struct Visitor {
  std::function<void(const DvlSample&)> dvl;
  std::function<void(const PressureSample&)> depth;
  std::function<void(const AttitudeSample&)> attitude;
  std::function<void(const NetObservation&, const Pose& truth)> camera;
};
void replay(const Sequence& seq, const Visitor& visit);

double median(std::vector<double> v);
double percentile(std::vector<double> v, double p);

}  // namespace pensight::global_pose::sim
