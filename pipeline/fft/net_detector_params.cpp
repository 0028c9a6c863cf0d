#include "pipeline/fft/net_detector_params.h"

#include <limits>
#include <numbers>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/params.h"

namespace pensight {

namespace {

constexpr ParamRange range_at_least(double min) {
  return {min, std::numeric_limits<double>::infinity()};
}
// (0, max]: a share, an angle, a threshold whose 0 would reject everything.
constexpr ParamRange range_above_zero_to(double max) {
  return {0, max, true, false};
}

constexpr double kRightAngle_rad = std::numbers::pi / 2;

// fft_size's power of two and its bound by the ROI side are explicit rules in validate().
const Param<NetDetectorConfig> kDetectorParams[] = {
    {"fft_size", &NetDetectorConfig::fft_size, "px", closed_range(0, 1024),
     "side the ROI is resampled to before its FFT (a power of two unless backend cpu; 16 to "
     "grid.roi_size_px); 0: planned, the largest power of two up to min(ROI, 256)"},
    {"window", &NetDetectorConfig::window, "", kAnyNumber, "separable Hann window on each ROI"},
    {"chirp_correction", &NetDetectorConfig::chirp_correction, "", kAnyNumber,
     "correct each ROI's lattice for its perspective chirp on the fitted plane and fit again"},
    {"bar_length_m", &NetDetectorConfig::bar_length_m, "m", kPositive,
     "bar length, knot to knot (scene.yaml net_mesh_size_m)"},
    {"mesh_angle_rad",
     &NetDetectorConfig::mesh_angle_rad,
     "rad",
     {0, std::numbers::pi, true, true},
     "prior opening angle (scene.yaml net_mesh_angle_deg); absent: estimated"},
    {"cpu_threads", &NetDetectorConfig::cpu_threads, "", kNonNegative,
     "CPU path threads (0: all hardware threads)"},
};

// roi_grid's own floor is 16 px; whether the grid fits the image needs the camera.
const Param<kernels::RoiGrid> kGridParams[] = {
    {"rows", &kernels::RoiGrid::rows, "", range_at_least(1), "ROI rows"},
    {"cols", &kernels::RoiGrid::cols, "", range_at_least(1), "ROI columns"},
    {"roi_size_px", &kernels::RoiGrid::roi_size_px, "px", range_at_least(0),
     "ROI side, at least 16; 0: planned from the camera's fx and the bar length (300 at fx 462 "
     "and 30 mm)"},
    {"border_px", &kernels::RoiGrid::border_px, "px", kNonNegative,
     "margin kept free at the image edges"},
};

// A ratio of 0 would reject every ROI (or, for the sub-harmonic, always halve the frequency);
// 1e9 switches a rule off (the ablation in docs/fft_detection.md).
const Param<kernels::PeakParams> kPeakParams[] = {
    {"min_cycles", &kernels::PeakParams::min_cycles, "cycles", kPositive,
     "lattice periods across the ROI below which a peak is taken for illumination or leakage"},
    {"max_nyquist_share", &kernels::PeakParams::max_nyquist_share, "", range_above_zero_to(1),
     "top of the peak band as a share of fft_size / 2 (above: resampling alias)"},
    {"beyond_band_ratio", &kernels::PeakParams::beyond_band_ratio, "", kPositive,
     "a bin above the band this strong against the band's peak: the band holds an alias"},
    {"min_angle_deg", &kernels::PeakParams::min_angle_deg, "deg", range_above_zero_to(90),
     "least angle between the two base frequency vectors"},
    {"subharmonic_ratio", &kernels::PeakParams::subharmonic_ratio, "", kPositive,
     "a peak at half the frequency this strong is the fundamental"},
    {"below_band_ratio", &kernels::PeakParams::below_band_ratio, "", kPositive,
     "a maximum below the band at half the frequency this strong: the net is coarser than the "
     "band"},
    {"subbin", &kernels::PeakParams::subbin, "", kAnyNumber,
     "log-parabolic sub-bin peak refinement (off: integer bins)"},
};

const Param<NetPointParams> kPointParams[] = {
    {"min_quality", &NetPointParams::min_quality, "", closed_range(0, 1),
     "least share of the ROI's spectral energy in the lattice peaks"},
    {"near_cycles", &NetPointParams::near_cycles, "cycles", kNonNegative,
     "a lattice with a base vector under this many periods across the ROI needs "
     "near_min_quality (illumination gradients leak there)"},
    {"near_min_quality", &NetPointParams::near_min_quality, "", closed_range(0, 1),
     "least share of the spectral energy in the peaks of a lattice under near_cycles"},
    {"min_period_px", &NetPointParams::min_period_px, "px", kNonNegative,
     "finer lattices are below what the resampled ROI can carry"},
    {"max_tilt_rad", &NetPointParams::max_tilt_rad, "rad", range_above_zero_to(kRightAngle_rad),
     "largest tilt of the net against the ROI's ray (beyond, the foreshortened period is "
     "unreliable)"},
    {"max_range_m", &NetPointParams::max_range_m, "m", kPositive, "farthest net point kept"},
    {"use_centroid", &NetPointParams::use_centroid, "", kAnyNumber,
     "place the point at the ROI's energy centroid (off: the ROI centre)"},
    {"max_centroid_share", &NetPointParams::max_centroid_share, "", range_above_zero_to(1),
     "energy centroid further from the ROI centre than this share of its side: a partial net"},
};

const Param<RelativePoseFftParams> kPoseParams[] = {
    {"min_valid_rois", &RelativePoseFftParams::min_valid_rois, "", range_at_least(3),
     "fewer ROIs with a lattice: no pose (a plane needs 3)"},
    {"inlier_rel", &RelativePoseFftParams::inlier_rel, "", kPositive,
     "plane residual over depth that still counts as on the net"},
    {"min_paraboloid_rois", &RelativePoseFftParams::min_paraboloid_rois, "", range_at_least(6),
     "fewer inliers: d_net from the plane (a paraboloid has 6 coefficients)"},
    {"full_support_rois", &RelativePoseFftParams::full_support_rois, "", range_at_least(3),
     "inlier ROIs at which the pose's quality is no longer lowered for support"},
    {"max_obliquity_rad", &RelativePoseFftParams::max_obliquity_rad, "rad",
     range_above_zero_to(kRightAngle_rad),
     "psi or pitch beyond this, either sign: no pose (net too oblique)"},
    {"max_curvature_share", &RelativePoseFftParams::max_curvature_share, "", kNonNegative,
     "paraboloid's d_net more than this share off the plane's: the plane's"},
    {"max_extrapolation_lever", &RelativePoseFftParams::max_extrapolation_lever, "", kPositive,
     "largest lever of d_net's extrapolation from the inlier nearest the optical axis"},
    {"max_tilt_disagreement_rad", &RelativePoseFftParams::max_tilt_disagreement_rad, "rad",
     range_above_zero_to(kRightAngle_rad),
     "largest median angle between the inliers' own normals and the plane's, or the wall's "
     "where the paraboloid through them curves like it (else no pose)"},
    {"wall_curvature_per_m", &RelativePoseFftParams::wall_curvature_per_m, "1/m",
     closed_range(0, 10),
     "the net wall's horizontal curvature: scene.yaml's 1 / pen_radius_m, 0 on a flat panel"},
    {"min_fold_angle_rad", &RelativePoseFftParams::min_fold_angle_rad, "rad",
     range_above_zero_to(kRightAngle_rad),
     "ROIs off the plane on a second plane tilted at least this much: a fold, the pose from the "
     "panel the optical axis meets"},
    {"max_roi_tilt_rad", &RelativePoseFftParams::max_roi_tilt_rad, "rad",
     range_above_zero_to(kRightAngle_rad),
     "largest angle between a ROI's own normal and the plane it supports"},
    {"check_tilts", &RelativePoseFftParams::check_tilts, "", kAnyNumber,
     "refuse a plane the ROIs' own tilts contradict (a lattice harmonic)"},
    {"fuse_roi_tilt", &RelativePoseFftParams::fuse_roi_tilt, "", kAnyNumber,
     "fuse the plane's slopes with the inliers' per-ROI slopes"},
};

const Param<NetTextureParams> kTextureParams[] = {
    {"enabled", &NetTextureParams::enabled, "", kAnyNumber,
     "measure the net texture's move at the image centre"},
    {"window_px", &NetTextureParams::window_px, "px", range_at_least(8),
     "side of the patch about the image centre"},
    {"max_roi_offset_share", &NetTextureParams::max_roi_offset_share, "", kPositive,
     "nearest valid ROI's centre within this share of the window side from the patch centre"},
    {"min_coherence", &NetTextureParams::min_coherence, "", closed_range(0, 1),
     "least lattice coefficient over the patch's windowed contrast"},
};

const Param<MeshAngleParams> kMeshAngleParams[] = {
    {"max_bar_mismatch", &MeshAngleParams::max_bar_mismatch, "", closed_range(0, 1),
     "a ROI whose two bars on the plane differ by more than this share is left out"},
    {"min_rois", &MeshAngleParams::min_rois, "", range_at_least(1),
     "fewer usable ROIs: no measurement"},
    {"diamond_bisector_rad", &MeshAngleParams::diamond_bisector_rad, "rad",
     closed_range(0, std::numbers::pi / 4),
     "bisector within this of the net's vertical or horizontal: a diamond mesh"},
    {"type_evidence_margin_rad", &MeshAngleParams::type_evidence_margin_rad, "rad",
     closed_range(0, std::numbers::pi / 4),
     "median bisector this far from diamond_bisector_rad: the frame's own mesh type, whatever "
     "scene.yaml says"},
};

// min_sigma_rad > 0 keeps the Kalman gain's denominator positive with a zero prior or process
// sigma.
const Param<MeshAngleFilter::Params> kMeshAngleFilterParams[] = {
    {"process_sigma_rad", &MeshAngleFilter::Params::process_sigma_rad, "rad", kNonNegative,
     "random walk of the opening angle per frame"},
    {"prior_sigma_rad", &MeshAngleFilter::Params::prior_sigma_rad, "rad", kNonNegative,
     "uncertainty of the prior opening angle"},
    {"min_sigma_rad", &MeshAngleFilter::Params::min_sigma_rad, "rad", kPositive,
     "floor of a frame's own sigma"},
    {"gate_sigmas", &MeshAngleFilter::Params::gate_sigmas, "", kPositive,
     "a measurement beyond this many sigmas is outside the gate"},
    {"restart_after", &MeshAngleFilter::Params::restart_after, "", range_at_least(1),
     "consecutive frames outside the gate before the filter restarts"},
};

constexpr const char* kDetectorWhere = "net detector config";

[[noreturn]] void refuse_detector_config(std::string_view key, const std::string& what) {
  std::string message(kDetectorWhere);
  message.append(": key '").append(key).append("': ").append(what);
  throw Error(message);
}

bool is_power_of_two(int n) {
  return n > 0 && (n & (n - 1)) == 0;
}

}  // namespace

void validate(const NetDetectorConfig& c) {
  check_params<NetDetectorConfig>(c, kDetectorParams, kDetectorWhere, "");
  check_params<kernels::RoiGrid>(c.grid, kGridParams, kDetectorWhere, "grid.");
  check_params<kernels::PeakParams>(c.peaks, kPeakParams, kDetectorWhere, "peaks.");
  check_params<NetPointParams>(c.points, kPointParams, kDetectorWhere, "points.");
  check_params<RelativePoseFftParams>(c.pose, kPoseParams, kDetectorWhere, "pose.");
  check_params<DepthPriorParams>(c.priors, depth_prior_params(), kDetectorWhere, "priors.");
  check_params<NetTextureParams>(c.texture, kTextureParams, kDetectorWhere, "texture.");
  check_params<MeshAngleParams>(c.mesh_angle, kMeshAngleParams, kDetectorWhere, "mesh_angle.");
  check_params<MeshAngleFilter::Params>(c.mesh_angle_filter, kMeshAngleFilterParams, kDetectorWhere,
                                        "mesh_angle_filter.");
  // 0: planned (grid_plan.h).
  if (c.grid.roi_size_px != 0 && c.grid.roi_size_px < kernels::kMinRoiSize_px) {
    refuse_detector_config("grid.roi_size_px",
                           format_param_value(c.grid.roi_size_px) +
                               " px is below 16; give 16 or more, or 0 to plan it from the camera");
  }
  if (c.fft_size != 0 && c.fft_size < kernels::kMinFftSize) {
    refuse_detector_config("fft_size", format_param_value(c.fft_size) +
                                           " px is below 16; give 16 or more, or 0 to plan it");
  }
  if (c.fft_size == 0) return;
  const std::string fft_size = format_param_value(c.fft_size);
  if (c.grid.roi_size_px != 0 && c.fft_size > c.grid.roi_size_px) {
    refuse_detector_config("fft_size", fft_size + " px is above grid.roi_size_px (" +
                                           format_param_value(c.grid.roi_size_px) +
                                           " px): resampling only shrinks");
  }
  if (c.backend != Backend::kCpu && !is_power_of_two(c.fft_size)) {
    refuse_detector_config("fft_size", fft_size + " px is not a power of two, which backend " +
                                           to_string(c.backend) +
                                           " may need (only cpu takes any size)");
  }
  const float band_top = c.peaks.max_nyquist_share * static_cast<float>(c.fft_size / 2);
  if (!(c.peaks.min_cycles < band_top)) {
    refuse_detector_config("peaks.min_cycles",
                           format_param_value(c.peaks.min_cycles) +
                               " cycles leaves no peak band below peaks.max_nyquist_share * "
                               "fft_size / 2 (" +
                               format_param_value(band_top) + " cycles)");
  }
}

std::string net_detector_param_rows() {
  const NetDetectorConfig d;
  std::string rows = param_table_rows<NetDetectorConfig>(kDetectorParams, d);
  rows += param_table_rows<kernels::RoiGrid>(kGridParams, d.grid, "grid.");
  rows += param_table_rows<kernels::PeakParams>(kPeakParams, d.peaks, "peaks.");
  rows += param_table_rows<NetPointParams>(kPointParams, d.points, "points.");
  rows += param_table_rows<RelativePoseFftParams>(kPoseParams, d.pose, "pose.");
  rows += param_table_rows<DepthPriorParams>(depth_prior_params(), d.priors, "priors.");
  rows += param_table_rows<NetTextureParams>(kTextureParams, d.texture, "texture.");
  rows += param_table_rows<MeshAngleParams>(kMeshAngleParams, d.mesh_angle, "mesh_angle.");
  rows += param_table_rows<MeshAngleFilter::Params>(kMeshAngleFilterParams, d.mesh_angle_filter,
                                                    "mesh_angle_filter.");
  return rows;
}

}  // namespace pensight
