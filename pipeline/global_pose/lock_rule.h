#pragma once
// When a single circle fit may set the filter's position on its own: at start-up (the first fix
// initialises the EKF) and to re-initialise it after the filter has gone wrong. A fit over the
// few ROIs at the image edge that see the net entering the view can be consistent to
// centimetres and metres wrong, so such a fix must wait for a better one.
#include <string>

#include "pipeline/global_pose/pen_fix.h"

namespace pensight::global_pose {

struct LockRule {
  int min_inliers = 12;                  // of the grid's ROIs (5 x 6 = 30)
  double min_bearing_spread_rad = 0.25;  // inliers' bearings seen from the body origin
  double max_residual_rms_m = 0.04;      // of the inliers to the fitted circle
  double max_r_sigma_m = 0.05;           // the fit's own standard deviation of r_g
  double max_abs_psi_r_rad = 0.45;       // facing the net within ~25 deg (oblique ROIs are worse)
  // Beyond it, up to this, where a recent DVL net plane agrees (estimator side): the DVL's beams
  // measure the plane apart from the ROIs whose obliquity makes the fit less sure.
  double max_abs_psi_r_with_plane_rad = 1.0;  // ~57 deg
  // Checked against the DVL net plane when one was measured this recently (estimator side).
  double max_plane_age_s = 0.3;
  double plane_distance_tol_m = 0.25;
  double plane_heading_tol_rad = 0.25;
  // Re-initialisation: after this many gated-out fixes in a row that pass the rule and whose
  // innovations agree with each other (lie within (agree_r_m, agree_psi_r_rad) of a straight
  // line in time: the filter's position is off, and maybe its velocity), the position and
  // heading states are re-locked to the latest fix and the velocity corrected by the line's
  // slope. Fewer than 2 turns it off.
  int reinit_after_rejected_fixes = 3;
  double agree_r_m = 0.05;
  double agree_psi_r_rad = 0.05;
};

// Whether a fix may set the position on its own, and if not, why.
enum class LockVerdict {
  kLockable,
  kNoFit,
  kFewInliers,
  kNarrowSpread,
  kHighResidual,
  kUncertainDistance,
  kOblique,
  kMissesThePanel,         // estimator side: the azimuth's ray misses the flat panel
  kDisagreesWithDvlPlane,  // estimator side: a recent DVL net plane says otherwise
};

struct LockCheck {
  LockVerdict verdict = LockVerdict::kLockable;
  std::string reason;  // for the log, e.g. "7 inliers < 12"; empty when lockable
  bool lockable() const { return verdict == LockVerdict::kLockable; }
};

// The fit's own part of the rule (the estimator adds the flat panel and the DVL plane).
LockCheck check_lock(const PenFix& fix, const LockRule& rule);

}  // namespace pensight::global_pose
