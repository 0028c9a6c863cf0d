#pragma once
// Net-relative pose from the FFT detector's per-ROI net points: a robust weighted least-squares
// plane z = a x + b y + c through the valid 3D points in C gives psi_net = atan(a) and
// pitch_net = atan(b) (signs as in ../shared/dataset-format.md); a weighted paraboloid
// z = c0 + a x + b y + q1 x^2 + q2 x y + q3 y^2 through the same inliers gives d_net = c0, the
// net's depth on the optical axis (x = y = 0), which follows a curved pen wall; a curvature term
// only where the inliers sit in at least 4 grid columns (x^2), rows (y^2) or both (x y).
// Outlier ROIs (a harmonic taken for the fundamental, a fish, a reflection) are removed by an
// exhaustive three-point consensus before the fit. The plane's slopes are then fused with the
// inliers' own tilts (RoiNetPoint::normals_C), which need no baseline: where the net covers only
// part of the image the points span a short baseline and the plane's slope is poorly determined.
// Fewer valid ROIs than the minimum, or no consistent plane: NaN and a reason.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/dataset_types.h"
#include "core/units.h"
#include "pipeline/fft/net_geometry.h"

namespace pensight {

struct RelativePoseFftParams {
  int min_valid_rois = 6;
  double inlier_rel = 0.05;      // plane residual / depth that still counts as on the net
  int min_paraboloid_rois = 12;  // fewer inliers: d_net from the plane
  // FftRelativePose::quality scales with the inlier count up to this many.
  int full_support_rois = 12;
  // |psi| or |pitch| beyond 57 deg: NaN, "net too oblique". |psi| reads 2-3 deg low at 50-60 deg
  // and more beyond, so this is a true ~60 deg; estimates of 58-60 deg came from nets at up to
  // 67 deg with d_net 13-21 % off, those up to 58 deg within 9 %.
  double max_obliquity_rad = 0.995;
  double max_curvature_share = 0.1;  // paraboloid's d_net more than this off the plane's: use plane
  // d_net is the plane's depth on the optical axis, extrapolated from the inlier nearest to it.
  // Its relative error per radian of slope error there is |x| / cos^2(psi) + |y| / cos^2(pitch)
  // (x, y: the inlier's normalised image coordinates). |psi| reads 10-17 deg low at 65-72 deg
  // (perspective within a ROI), and at a lever of 1 that is a d_net 20-40 % off. Frames within
  // 10 % gave at most 0.47, half nets (the net ends at the optical axis) at most 0.31.
  double max_extrapolation_lever = 0.7;
  // The median angle between the inliers' own normals and the plane's. A lattice harmonic taken
  // for the fundamental in every ROI still fits a plane, but not the ROIs' tilts (19 deg at
  // 79 deg); 360 synthetic frames within the envelope stayed below 5 deg.
  double max_tilt_disagreement_rad = 0.14;  // 8 deg
  // The pen wall's horizontal curvature (scene.yaml: 1 / pen_radius_m, 0 on a flat panel). The
  // inliers' tilts may agree with the paraboloid through them instead of the plane when it curves
  // no more than such a wall.
  double wall_curvature_per_m = 1 / kDefaultPenRadius_m;
  // A ROI whose own tilt is further than this from a candidate plane's does not support it (a
  // rope, seam, fold or fish across the ROI); the pose comes from the ROIs that agree, and from
  // the points alone when too few do.
  double max_roi_tilt_rad = 0.28;  // 16 deg
  // ROIs off the fitted plane that fit a second one tilted at least this much from it, meeting it
  // in a fold (two panels, a seam), as many as a pose needs: the pose is that of the panel the
  // optical axis meets, the other panel's ROIs are named (FftRelativePose::second_panel). Below
  // 5 deg the two panels' depths differ by less than inlier_rel over the frame, one plane.
  double min_fold_angle_rad = 0.087;  // 5 deg
  // Off for a plane from the points alone (the tilts then do not count): the net's opening
  // angle is measured against it before the ROIs' tilts can be trusted (mesh_angle.h).
  bool check_tilts = true;
  // Fuse the plane's slopes with the mean of the inliers' per-ROI slopes, weighted by inverse
  // variance: the plane's from its residuals, the per-ROI mean's the spread of the per-ROI slopes
  // itself (not divided by their count: their errors share a bias, |slope| low by up to ~5 % at
  // 20-30 deg, so they do not average out). Full nets: the plane dominates.
  bool fuse_roi_tilt = true;
};

// Why an FFT relative pose is NaN (kValid when it is not).
enum class FftPoseStatus {
  kValid,
  kTooFewRois,     // fewer ROIs with a lattice than min_valid_rois
  kNoConsensus,    // no plane agrees with enough of the net points
  kRefitLost,      // the refitted plane keeps too few of them
  kTooOblique,     // beyond max_obliquity_rad
  kExtrapolated,   // net points too far from the optical axis for the obliquity
  kTiltsDisagree,  // the ROIs' own tilts contradict the plane (a lattice harmonic)
};

struct FftRelativePose {
  FftPoseStatus status = FftPoseStatus::kTooFewRois;
  double d_net_m = kNaN;
  double psi_net_rad = kNaN;
  double pitch_net_rad = kNaN;
  int valid_rois = 0;            // ROIs with a usable lattice
  int inlier_rois = 0;           // of those, on the fitted surface
  double rms_residual_m = kNaN;  // of the inliers about the fitted surface
  std::vector<uint8_t> inlier;   // per input ROI: 1 when it supports the fitted surface
  std::string reason;            // status in words with its numbers; empty when valid
  // Per input ROI (empty without a pose): 1 when its net point lies on the fitted surface but its
  // own lattice is tilted otherwise (a rope, seam or fold across the ROI), so it was left out.
  std::vector<uint8_t> other_tilt;
  // Per input ROI (empty without a pose): 1 on the other panel of a fold (min_fold_angle_rad),
  // left out of the pose, which is the panel's the optical axis meets.
  std::vector<uint8_t> second_panel;
  // How far the pose stayed from being refused, in [0, 1] (0 without a pose): the product of the
  // inliers' support (their count over full_support_rois, at most 1), their share of the valid
  // ROIs, and each check's margin 1 - value / limit (obliquity, extrapolation lever, the inliers'
  // tilt disagreement, the fit's rms residual over inlier_rel x d_net). Downstream stages weigh
  // the pose by pose_trust() of it (core/pose_trust.h).
  double quality = 0;
  // The net surface the pose is of, z = c . (1, x, y, x^2, x y, y^2) in C (NaN without a pose):
  // c0 = d_net_m, (c1, c2) = (tan psi_net, tan pitch_net), and the curvature terms of the
  // paraboloid through the inliers where it curves like the pen wall; where only some of its
  // terms do, those of the paraboloid refitted with them alone when it then does; else 0 (a
  // plane).
  Eigen::Matrix<double, 6, 1> surface_C = Eigen::Matrix<double, 6, 1>::Constant(kNaN);
  bool valid() const { return status == FftPoseStatus::kValid; }
};

// Unit normal, pointing at the camera, of the plane z = slope_x x + slope_y y + c in C
// (slopes tan(psi_net), tan(pitch_net)).
Eigen::Vector3d net_plane_normal(double slope_x, double slope_y);

// Unit normal, oriented as net_plane_normal, of the surface z = c . (1, x, y, x^2, x y, y^2)
// (FftRelativePose::surface_C) at the point p_C.
Eigen::Vector3d net_surface_normal(const Eigen::Matrix<double, 6, 1>& c,
                                   const Eigen::Vector3d& p_C);

FftRelativePose relative_pose_fft(std::span<const RoiNetPoint> rois,
                                  const RelativePoseFftParams& params = {});

}  // namespace pensight
