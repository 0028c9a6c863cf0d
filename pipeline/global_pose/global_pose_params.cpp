// The parameter tables of the global-pose estimator and the published node (core/params.h): one
// per config struct, the nested ones under their member's name ("noise.process.yaw_accel").
#include <Eigen/Core>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/params.h"
#include "pipeline/global_pose/global_pose_estimator.h"
#include "pipeline/global_pose/published_global_pose.h"

namespace pensight::global_pose {
namespace {

// A count of samples or iterations that must happen at least once.
constexpr ParamRange kPoseCountRange{1, std::numeric_limits<double>::infinity()};

// Measurement noise enters the innovation covariance, whose inverse gates every update: it must
// be > 0. A process noise of 0 keeps its state from wandering, which the filter allows.
const Param<ProcessNoise> kProcessNoiseParams[] = {
    {"horizontal_accel", &ProcessNoise::horizontal_accel, "m/s^2/sqrt(Hz)", kNonNegative,
     "horizontal acceleration, manoeuvring"},
    {"quiet_horizontal_accel", &ProcessNoise::quiet_horizontal_accel, "m/s^2/sqrt(Hz)",
     kNonNegative, "horizontal acceleration, following or holding station"},
    {"vertical_accel", &ProcessNoise::vertical_accel, "m/s^2/sqrt(Hz)", kNonNegative,
     "vertical acceleration"},
    {"yaw_accel", &ProcessNoise::yaw_accel, "rad/s^2/sqrt(Hz)", kNonNegative, "yaw acceleration"},
    {"yaw_bias_walk", &ProcessNoise::yaw_bias_walk, "rad/sqrt(s)", kNonNegative,
     "drift of the attitude sensor's yaw"},
    {"dvl_bias_walk", &ProcessNoise::dvl_bias_walk, "m/s/sqrt(s)", kNonNegative,
     "drift of the DVL's velocity error (a scale error changes with the speed)"},
    {"fix_heading_bias_rad", &ProcessNoise::fix_heading_bias_rad, "rad", kNonNegative,
     "the vision heading error's stationary standard deviation"},
    {"fix_heading_bias_time_s", &ProcessNoise::fix_heading_bias_time_s, "s", kPositive,
     "the vision heading error's correlation time"},
};

const Param<MeasurementNoise> kPoseNoiseParams[] = {
    {"dvl_velocity_mps", &MeasurementNoise::dvl_velocity_mps, "m/s", kPositive,
     "DVL velocity per axis; also the spike test's sample noise"},
    {"dvl_bias_prior_mps", &MeasurementNoise::dvl_bias_prior_mps, "m/s", kPositive,
     "prior on the DVL's horizontal velocity error (scale and offset)"},
    {"depth_m", &MeasurementNoise::depth_m, "m", kPositive, "pressure depth"},
    {"attitude_yaw_rad", &MeasurementNoise::attitude_yaw_rad, "rad", kPositive,
     "the attitude sensor's yaw"},
    {"fix_r_floor_m", &MeasurementNoise::fix_r_floor_m, "m", kPositive,
     "vision fix: floor on r_g beside the circle fit's covariance"},
    {"fix_psi_r_floor_rad", &MeasurementNoise::fix_psi_r_floor_rad, "rad", kPositive,
     "vision fix: floor on psi_r beside the circle fit's covariance"},
    {"fix_inflation", &MeasurementNoise::fix_inflation, "", kPositive,
     "vision fix: multiplies the circle fit's standard deviations (the ROIs' errors correlate)"},
    {"d_net_frac", &MeasurementNoise::d_net_frac, "", kPositive, "vision d_net, relative to d_net"},
    {"psi_net_rad", &MeasurementNoise::psi_net_rad, "rad", kPositive, "vision psi_net"},
    {"dvl_plane_distance_m", &MeasurementNoise::dvl_plane_distance_m, "m", kPositive,
     "DVL net plane's distance"},
    {"dvl_plane_heading_rad", &MeasurementNoise::dvl_plane_heading_rad, "rad", kPositive,
     "DVL net plane's heading"},
    {"net_texture_m", &MeasurementNoise::net_texture_m, "m", kPositive,
     "net texture odometer against the centre ray's along-wall coordinate"},
    {"net_texture_step_m", &MeasurementNoise::net_texture_step_m, "m", kNonNegative,
     "error each odometer step adds: the lattice phase's noise"},
    {"net_texture_step_frac", &MeasurementNoise::net_texture_step_frac, "", kNonNegative,
     "error each odometer step adds, relative to the step: the bars' direction"},
    {"net_texture_yaw_rate_window_s", &MeasurementNoise::net_texture_yaw_rate_window_s, "s",
     kPositive, "the attitude's yaw rate that predicts the odometer's move: over this window"},
    // Beyond half a bar the nearest whole count is no longer the likelier one.
    {"net_texture_max_unwrap_bars",
     &MeasurementNoise::net_texture_max_unwrap_bars,
     "bars",
     {0, 0.5, true, false},
     "whole bars are counted only where the move is this near the predicted one"},
};

// Standard deviations of states no measurement sets yet: each must leave the state uncertain.
const Param<FilterPriors> kPosePriorParams[] = {
    {"position_along_wall_m", &FilterPriors::position_along_wall_m, "m", kPositive,
     "along the wall at the lock (rho_g is initial_rho_rad there by definition)"},
    {"depth_without_pressure_m", &FilterPriors::depth_without_pressure_m, "m", kPositive,
     "depth at the lock without a pressure sample"},
    {"velocity_without_dvl_mps", &FilterPriors::velocity_without_dvl_mps, "m/s", kPositive,
     "velocity at the lock without a DVL sample"},
    {"psi_rate_radps", &FilterPriors::psi_rate_radps, "rad/s", kPositive,
     "yaw rate at the lock without attitude samples"},
    {"psi_rate_window_s", &FilterPriors::psi_rate_window_s, "s", kPositive,
     "the yaw rate at the lock: from two attitude samples this far apart"},
    {"psi_rate_from_attitude_radps", &FilterPriors::psi_rate_from_attitude_radps, "rad/s",
     kPositive, "that yaw rate's standard deviation"},
    {"attitude_yaw_offset_rad", &FilterPriors::attitude_yaw_offset_rad, "rad", kPositive,
     "the attitude yaw's offset (any; the first sample sets it)"},
    {"velocity_after_reinit_mps", &FilterPriors::velocity_after_reinit_mps, "m/s", kPositive,
     "velocity after a re-initialisation from agreeing fixes (the DVL sets it again)"},
    {"released_velocity_mps", &FilterPriors::released_velocity_mps, "m/s", kPositive,
     "velocity released when the DVL or the pressure sensor re-locks"},
    {"released_heading_rad", &FilterPriors::released_heading_rad, "rad", kPositive,
     "heading released when the attitude yaw re-locks"},
    {"released_psi_rate_radps", &FilterPriors::released_psi_rate_radps, "rad/s", kPositive,
     "yaw rate released when the attitude yaw re-locks"},
    {"released_depth_m", &FilterPriors::released_depth_m, "m", kPositive,
     "depth released when the pressure sensor re-locks"},
};

// radius_m is no parameter: the estimator and the published node set it from pen_radius_m. The
// Gauss-Newton refinement needs one iteration to give a covariance; fewer than 3 inliers count as
// 3.
const Param<CircleFitOptions> kCircleParams[] = {
    {"huber_delta_m", &CircleFitOptions::huber_delta_m, "m", kPositive,
     "residuals beyond this are down-weighted (Huber); about 2-3x the point noise"},
    {"outlier_threshold_m", &CircleFitOptions::outlier_threshold_m, "m", kPositive,
     "points farther than this from the circle are left out of the final fit"},
    {"max_iterations", &CircleFitOptions::max_iterations, "", kPoseCountRange,
     "Gauss-Newton iterations at most"},
    {"max_hypotheses", &CircleFitOptions::max_hypotheses, "", kNonNegative,
     "2-point MSAC hypotheses at most (beside the line fit's)"},
    {"min_inliers", &CircleFitOptions::min_inliers, "", kNonNegative,
     "fewest inliers of a fit (3 at least in any case)"},
};

const Param<LockRule> kLockRuleParams[] = {
    {"min_inliers", &LockRule::min_inliers, "", kNonNegative,
     "fewest circle-fit inliers of a fix that may lock (of the grid's 30 ROIs)"},
    {"min_bearing_spread_rad", &LockRule::min_bearing_spread_rad, "rad", kNonNegative,
     "narrowest spread of the inliers' bearings from the body origin"},
    {"max_residual_rms_m", &LockRule::max_residual_rms_m, "m", kPositive,
     "largest RMS of the inliers to the fitted circle"},
    {"max_r_sigma_m", &LockRule::max_r_sigma_m, "m", kPositive,
     "largest standard deviation of r_g the fit gives"},
    {"max_abs_psi_r_rad", &LockRule::max_abs_psi_r_rad, "rad", kPositive,
     "facing the net within this (oblique ROIs are worse)"},
    {"max_abs_psi_r_with_plane_rad", &LockRule::max_abs_psi_r_with_plane_rad, "rad", kPositive,
     "beyond max_abs_psi_r_rad, up to this where a recent DVL net plane agrees with the fix"},
    {"max_plane_age_s", &LockRule::max_plane_age_s, "s", kNonNegative,
     "a DVL net plane measured this recently must agree with the fix"},
    {"plane_distance_tol_m", &LockRule::plane_distance_tol_m, "m", kPositive,
     "agreement with the DVL net plane's distance"},
    {"plane_heading_tol_rad", &LockRule::plane_heading_tol_rad, "rad", kPositive,
     "agreement with the DVL net plane's heading"},
    {"reinit_after_rejected_fixes", &LockRule::reinit_after_rejected_fixes, "", kNonNegative,
     "agreeing gated-out fixes in a row that re-lock the position (fewer than 2: never)"},
    {"agree_r_m", &LockRule::agree_r_m, "m", kPositive,
     "such fixes agree: their r innovations within this of a line in time"},
    {"agree_psi_r_rad", &LockRule::agree_psi_r_rad, "rad", kPositive,
     "such fixes agree: their psi_r innovations within this of a line in time"},
};

// noise_mps is no parameter: the estimator sets it from noise.dvl_velocity_mps.
const Param<DvlSpikeTestOptions> kDvlSpikeParams[] = {
    {"max_accel_mps2", &DvlSpikeTestOptions::max_accel_mps2, "m/s^2", kPositive,
     "the vehicle's acceleration stays below this"},
    {"noise_sigmas", &DvlSpikeTestOptions::noise_sigmas, "", kNonNegative,
     "margin on the difference of two samples' noise, in standard deviations"},
    {"max_spike_samples", &DvlSpikeTestOptions::max_spike_samples, "", kNonNegative,
     "a spike lasts at most this many samples; a longer change is a manoeuvre"},
    {"max_hold_s", &DvlSpikeTestOptions::max_hold_s, "s", kNonNegative,
     "suspect samples with no later sample for this long are dropped as spikes"},
};

const Param<GlobalPoseEstimatorConfig> kPoseEstimatorParams[] = {
    {"pen_radius_m", &GlobalPoseEstimatorConfig::pen_radius_m, "m", kPositive,
     "scene.yaml pen_radius_m; a flat net is a large radius (100 m)"},
    {"initial_rho_rad", &GlobalPoseEstimatorConfig::initial_rho_rad, "rad", kAnyNumber,
     "rho_g at the lock"},
    {"has_dvl", &GlobalPoseEstimatorConfig::has_dvl, "", {}, "the dataset has a DVL (dvl0/)"},
    {"has_attitude",
     &GlobalPoseEstimatorConfig::has_attitude,
     "",
     {},
     "the dataset has attitude (imu0/attitude.csv)"},
    {"has_pressure",
     &GlobalPoseEstimatorConfig::has_pressure,
     "",
     {},
     "the dataset has pressure depth (pressure0/)"},
    {"use_attitude_yaw",
     &GlobalPoseEstimatorConfig::use_attitude_yaw,
     "",
     {},
     "aid the heading with the attitude sensor's yaw"},
    {"use_vision_relative",
     &GlobalPoseEstimatorConfig::use_vision_relative,
     "",
     {},
     "fuse the vision d_net and psi_net"},
    {"use_dvl_plane",
     &GlobalPoseEstimatorConfig::use_dvl_plane,
     "",
     {},
     "fuse the DVL net plane (with the DVL's beam geometry)"},
    {"use_net_texture",
     &GlobalPoseEstimatorConfig::use_net_texture,
     "",
     {},
     "fuse the net texture odometry"},
    {"gate_scale", &GlobalPoseEstimatorConfig::gate_scale, "", kPositive,
     "multiplies the chi-square gates (p = 0.999)"},
    {"relock_after_rejections", &GlobalPoseEstimatorConfig::relock_after_rejections, "",
     kPoseCountRange, "rejections in a row after which a sensor's next sample skips the gate"},
    {"motion_relock_after_rejections", &GlobalPoseEstimatorConfig::motion_relock_after_rejections,
     "", kPoseCountRange,
     "rejections in a row of DVL velocity, attitude yaw or depth that release their states"},
    {"history_s", &GlobalPoseEstimatorConfig::history_s, "s", kNonNegative,
     "late samples up to this far behind the filter are re-applied"},
    {"max_attitude_gap_s", &GlobalPoseEstimatorConfig::max_attitude_gap_s, "s", kNonNegative,
     "attitude is interpolated across gaps up to this"},
    {"max_rho_sigma_rad", &GlobalPoseEstimatorConfig::max_rho_sigma_rad, "rad", kPositive,
     "beyond this standard deviation rho_g and psi_g are NaN"},
    {"max_unaided_s", &GlobalPoseEstimatorConfig::max_unaided_s, "s", kNonNegative,
     "rho_g and psi_g are NaN after this long without DVL velocity or attitude yaw"},
    {"max_z_sigma_m", &GlobalPoseEstimatorConfig::max_z_sigma_m, "m", kPositive,
     "beyond this standard deviation z_g is NaN"},
};

const Param<PublishedGlobalPoseConfig> kPublishedParams[] = {
    {"pen_radius_m", &PublishedGlobalPoseConfig::pen_radius_m, "m", kPositive,
     "scene.yaml pen_radius_m; a flat net is a large radius (100 m)"},
    {"level_with_attitude",
     &PublishedGlobalPoseConfig::level_with_attitude,
     "",
     {},
     "level with the latest attitude (false: roll = pitch = 0, as published)"},
    {"has_dvl", &PublishedGlobalPoseConfig::has_dvl, "", {}, "the dataset has a DVL (dvl0/)"},
    {"initial_rho_rad", &PublishedGlobalPoseConfig::initial_rho_rad, "rad", kAnyNumber,
     "rho_g at the first fix"},
    {"max_dvl_gap_s", &PublishedGlobalPoseConfig::max_dvl_gap_s, "s", kNonNegative,
     "a longer gap between valid DVL samples is not integrated"},
};

constexpr const char* kPoseWhere = "global pose";
constexpr const char* kPublishedWhere = "global pose (published)";

}  // namespace

void validate(const GlobalPoseEstimatorConfig& c) {
  check_params<GlobalPoseEstimatorConfig>(c, kPoseEstimatorParams, kPoseWhere);
  check_params<CircleFitOptions>(c.circle, kCircleParams, kPoseWhere, "circle.");
  check_params<MeasurementNoise>(c.noise, kPoseNoiseParams, kPoseWhere, "noise.");
  check_params<ProcessNoise>(c.noise.process, kProcessNoiseParams, kPoseWhere, "noise.process.");
  check_params<FilterPriors>(c.priors, kPosePriorParams, kPoseWhere, "priors.");
  check_params<LockRule>(c.lock, kLockRuleParams, kPoseWhere, "lock.");
  check_params<DvlSpikeTestOptions>(c.dvl_spikes, kDvlSpikeParams, kPoseWhere, "dvl_spikes.");
  if (c.flat_panel) {
    // The wall model takes it as the outward normal, as a cylinder's, and needs the panel off the
    // origin.
    const Eigen::Vector2d normal = c.flat_panel->plane_normal.head<2>();
    const Eigen::Vector2d point = c.flat_panel->plane_point_m.head<2>();
    if (!(normal.norm() > 0.5) || !(normal.normalized().dot(point) > 0)) {
      throw Error(std::string(kPoseWhere) +
                  ": key 'flat_panel.plane_normal': must be horizontal and point away from the "
                  "pen frame's origin (scene.yaml net_plane_normal, net_plane_point_m)");
    }
  }
}

void validate(const PublishedGlobalPoseConfig& c) {
  check_params<PublishedGlobalPoseConfig>(c, kPublishedParams, kPublishedWhere);
  check_params<CircleFitOptions>(c.circle, kCircleParams, kPublishedWhere, "circle.");
}

std::string global_pose_param_rows() {
  const GlobalPoseEstimatorConfig d;
  std::string rows = param_table_rows<GlobalPoseEstimatorConfig>(kPoseEstimatorParams, d);
  rows += param_table_rows<CircleFitOptions>(kCircleParams, d.circle, "circle.");
  rows += param_table_rows<MeasurementNoise>(kPoseNoiseParams, d.noise, "noise.");
  rows += param_table_rows<ProcessNoise>(kProcessNoiseParams, d.noise.process, "noise.process.");
  rows += param_table_rows<FilterPriors>(kPosePriorParams, d.priors, "priors.");
  rows += param_table_rows<LockRule>(kLockRuleParams, d.lock, "lock.");
  rows += param_table_rows<DvlSpikeTestOptions>(kDvlSpikeParams, d.dvl_spikes, "dvl_spikes.");
  return rows;
}

std::string published_global_pose_param_rows() {
  const PublishedGlobalPoseConfig d;
  return param_table_rows<PublishedGlobalPoseConfig>(kPublishedParams, d) +
         param_table_rows<CircleFitOptions>(kCircleParams, d.circle, "circle.");
}

}  // namespace pensight::global_pose
