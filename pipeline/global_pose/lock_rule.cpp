#include "pipeline/global_pose/lock_rule.h"

#include <cmath>
#include <cstdio>

namespace pensight::global_pose {

LockCheck check_lock(const PenFix& fix, const LockRule& rule) {
  char why[96] = "";
  LockVerdict verdict = LockVerdict::kLockable;
  if (!fix.ok) {
    verdict = LockVerdict::kNoFit;
    std::snprintf(why, sizeof(why), "no circle fit");
  } else if (fix.circle.inliers < rule.min_inliers) {
    verdict = LockVerdict::kFewInliers;
    std::snprintf(why, sizeof(why), "%d inliers < %d", fix.circle.inliers, rule.min_inliers);
  } else if (!(fix.circle.inlier_bearing_spread_rad >= rule.min_bearing_spread_rad)) {
    verdict = LockVerdict::kNarrowSpread;
    std::snprintf(why, sizeof(why), "inliers span %.2f rad < %.2f",
                  fix.circle.inlier_bearing_spread_rad, rule.min_bearing_spread_rad);
  } else if (!(fix.circle.residual_rms_m <= rule.max_residual_rms_m)) {
    verdict = LockVerdict::kHighResidual;
    std::snprintf(why, sizeof(why), "residual rms %.3f m > %.3f", fix.circle.residual_rms_m,
                  rule.max_residual_rms_m);
  } else if (!(std::sqrt(fix.covariance(0, 0)) <= rule.max_r_sigma_m)) {
    verdict = LockVerdict::kUncertainDistance;
    std::snprintf(why, sizeof(why), "sigma(r_g) %.3f m > %.3f", std::sqrt(fix.covariance(0, 0)),
                  rule.max_r_sigma_m);
  } else if (!(std::abs(fix.psi_r_rad) <= rule.max_abs_psi_r_rad)) {
    verdict = LockVerdict::kOblique;
    std::snprintf(why, sizeof(why), "|psi_r| %.2f rad > %.2f", fix.psi_r_rad,
                  rule.max_abs_psi_r_rad);
  }
  return {verdict, why};
}

}  // namespace pensight::global_pose
