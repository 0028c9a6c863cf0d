// The parameter tables of the dense-depth stage (core/params.h): the estimator, the pose from
// dense depth under "plane.", and the DVL's corrections under their PipelineConfig names.
#include <limits>
#include <string>

#include "core/params.h"
#include "pipeline/depth/depth_estimator.h"
#include "pipeline/depth/depth_plane.h"
#include "pipeline/depth/dvl_depth_scale.h"
#include "pipeline/depth/dvl_net_tilt.h"

namespace pensight {
namespace {

// A count of samples or iterations that must happen at least once.
constexpr ParamRange kDepthCountRange{1, std::numeric_limits<double>::infinity()};

// A negative curvature would fit the prior surface as a flat wall, silently.
const Param<DepthEstimatorConfig> kDepthEstimatorParams[] = {
    {"cpu_threads", &DepthEstimatorConfig::cpu_threads, "", kNonNegative,
     "threads of the network on the CPU (0: all hardware threads)"},
    {"sigma_px", &DepthEstimatorConfig::sigma_px, "px", kPositive,
     "S2's radius in network pixels, as in training"},
    {"net_curvature_per_m", &DepthEstimatorConfig::net_curvature_per_m, "1/m", kNonNegative,
     "the net wall's curvature for the prior surface (1 / pen radius; 0: flat)"},
};

// A central window or an iteration count of 0 leaves no pixel to average or weigh: no pose.
const Param<DepthPlaneParams> kDepthPlaneParams[] = {
    {"central_share",
     &DepthPlaneParams::central_share,
     "",
     {0, 1, true, false},
     "d_net window: this share of the width and height, centred"},
    {"hypotheses", &DepthPlaneParams::hypotheses, "", kDepthCountRange,
     "three-pixel planes tried for the consensus start"},
    {"inlier_rel", &DepthPlaneParams::inlier_rel, "", kPositive,
     "residual / depth that still counts as on the net"},
    {"iterations", &DepthPlaneParams::iterations, "", kDepthCountRange,
     "reweighted least-squares iterations"},
    {"min_valid_share", &DepthPlaneParams::min_valid_share, "", closed_range(0, 1),
     "with a smaller share of pixels with depth the pose is NaN"},
};

// A spot's side squared counts pixels in an int: 1000 px is far beyond any beam's spot.
const Param<DvlDepthScaleConfig> kDvlDepthScaleParams[] = {
    {"max_pair_dt_s", &DvlDepthScaleConfig::max_pair_dt_s, "s", kPositive,
     "a DVL sample pairs with the first frame at most this much later"},
    {"window_s", &DvlDepthScaleConfig::window_s, "s", kPositive,
     "the median's window; the net's stretch varies over metres"},
    {"min_samples", &DvlDepthScaleConfig::min_samples, "", kDepthCountRange,
     "fewest samples in the window"},
    {"trusted_rel", &DvlDepthScaleConfig::trusted_rel, "", kNonNegative,
     "scene.yaml's bar length is right within this"},
    {"confidence_z", &DvlDepthScaleConfig::confidence_z, "", kNonNegative,
     "|median| must exceed trusted_rel by this many standard errors"},
    {"spot_half_px", &DvlDepthScaleConfig::spot_half_px, "px", closed_range(0, 1000),
     "the dense depth at a beam spot: the median over a (2 h + 1)^2 window"},
    {"max_two_beam_spread", &DvlDepthScaleConfig::max_two_beam_spread, "", kPositive,
     "two beams whose log ratios differ by more: one of them is not on the net"},
};

const Param<DvlNetTiltConfig> kDvlNetTiltParams[] = {
    {"max_pair_dt_s", &DvlNetTiltConfig::max_pair_dt_s, "s", kPositive,
     "a DVL sample pairs with the first frame at most this much later"},
    {"window_s", &DvlNetTiltConfig::window_s, "s", kPositive,
     "the median's window; the look point moves with the heading"},
    {"min_samples", &DvlNetTiltConfig::min_samples, "", kDepthCountRange,
     "fewest samples in the window"},
    {"trusted_rad", &DvlNetTiltConfig::trusted_rad, "rad", kNonNegative,
     "the camera's tilt is right within this"},
    {"confidence_z", &DvlNetTiltConfig::confidence_z, "", kNonNegative,
     "|median| must exceed trusted_rad by this many standard errors"},
    {"max_residual_m", &DvlNetTiltConfig::max_residual_m, "m", kPositive,
     "beam end points' RMS distance from their plane beyond which a beam is off the net"},
    {"range_noise_m", &DvlNetTiltConfig::range_noise_m, "m", kNonNegative,
     "the DVL's range noise, 1 sigma: the floor of the window's standard error"},
};

constexpr const char* kDepthWhere = "depth";

}  // namespace

void validate(const DepthEstimatorConfig& c) {
  check_params<DepthEstimatorConfig>(c, kDepthEstimatorParams, kDepthWhere);
  check_params<DepthPlaneParams>(c.plane, kDepthPlaneParams, kDepthWhere, "plane.");
}

void validate(const DvlDepthScaleConfig& c) {
  check_params<DvlDepthScaleConfig>(c, kDvlDepthScaleParams, kDepthWhere, "dvl_depth_scale.");
}

void validate(const DvlNetTiltConfig& c) {
  check_params<DvlNetTiltConfig>(c, kDvlNetTiltParams, kDepthWhere, "dvl_net_tilt.");
}

std::string depth_param_rows() {
  const DepthEstimatorConfig d;
  std::string rows = param_table_rows<DepthEstimatorConfig>(kDepthEstimatorParams, d);
  rows += param_table_rows<DepthPlaneParams>(kDepthPlaneParams, d.plane, "plane.");
  rows += param_table_rows<DvlDepthScaleConfig>(kDvlDepthScaleParams, {}, "dvl_depth_scale.");
  rows += param_table_rows<DvlNetTiltConfig>(kDvlNetTiltParams, {}, "dvl_net_tilt.");
  return rows;
}

}  // namespace pensight
