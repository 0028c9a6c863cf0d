#pragma once
// The published global-pose node, reproduced as the baseline: per camera frame a circle fit of
// the known pen radius gives r_g and psi_r; rho_g integrates the tangential component of the DVL's
// horizontal velocity over r_g; z_g is the latest pressure depth; psi_g = rho_g + psi_r. Samples
// are used in the order they are given, each sensor's latest value held (as the node did).
#include <Eigen/Geometry>
#include <string>

#include "core/dataset_types.h"
#include "pipeline/global_pose/measurements.h"
#include "pipeline/global_pose/pen_fix.h"

namespace pensight::global_pose {

struct PublishedGlobalPoseConfig {
  double pen_radius_m = kDefaultPenRadius_m;
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();
  // false: roll = pitch = 0 (the published assumption); true: level with the latest attitude.
  bool level_with_attitude = false;
  bool has_dvl = true;
  double initial_rho_rad = 0.0;
  // A gap between valid DVL samples longer than this is not integrated.
  double max_dvl_gap_s = 1.0;
  CircleFitOptions circle;  // radius_m is overwritten with pen_radius_m
};

// Throws pensight::Error "global pose (published): key 'KEY': VALUE is outside RANGE UNIT (HELP)"
// for the first value out of its range (circle fit options under "circle.").
void validate(const PublishedGlobalPoseConfig& config);
// Every numeric and bool key of PublishedGlobalPoseConfig with its default, unit, valid range and
// help: the rows of a Markdown table under core/params.h's kParamTableHeader.
std::string published_global_pose_param_rows();

class PublishedGlobalPose {
 public:
  // Throws like validate().
  explicit PublishedGlobalPose(PublishedGlobalPoseConfig config);

  void add(const DvlSample& s);
  void add(const PressureSample& s);
  void add(const AttitudeSample& s);
  // Runs the fix on one camera frame and returns that frame's estimates row.
  GlobalPose add(const NetObservation& obs);

 private:
  PublishedGlobalPoseConfig cfg_;
  PenFix fix_;
  bool started_ = false;
  double rho_rad_ = kNaN;
  double depth_m_ = kNaN;
  double roll_rad_ = 0, pitch_rad_ = 0;
  int64_t last_dvl_ns_ = -1;
  bool warned_invalid_dvl_ = false;
};

}  // namespace pensight::global_pose
