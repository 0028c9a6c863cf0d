#include "pipeline/global_pose/lock_rule.h"

#include <cmath>
#include <cstdio>

namespace pensight::global_pose {

std::string lock_refusal(const PenFix& fix, const LockRule& rule) {
  char why[96] = "";
  if (!fix.ok)
    std::snprintf(why, sizeof(why), "no circle fit");
  else if (fix.circle.inliers < rule.min_inliers)
    std::snprintf(why, sizeof(why), "%d inliers < %d", fix.circle.inliers, rule.min_inliers);
  else if (!(fix.circle.inlier_bearing_spread_rad >= rule.min_bearing_spread_rad))
    std::snprintf(why, sizeof(why), "inliers span %.2f rad < %.2f",
                  fix.circle.inlier_bearing_spread_rad, rule.min_bearing_spread_rad);
  else if (!(fix.circle.residual_rms_m <= rule.max_residual_rms_m))
    std::snprintf(why, sizeof(why), "residual rms %.3f m > %.3f", fix.circle.residual_rms_m,
                  rule.max_residual_rms_m);
  else if (!(std::sqrt(fix.covariance(0, 0)) <= rule.max_r_sigma_m))
    std::snprintf(why, sizeof(why), "sigma(r_g) %.3f m > %.3f", std::sqrt(fix.covariance(0, 0)),
                  rule.max_r_sigma_m);
  else if (!(std::abs(fix.psi_r_rad) <= rule.max_abs_psi_r_rad))
    std::snprintf(why, sizeof(why), "|psi_r| %.2f rad > %.2f", fix.psi_r_rad,
                  rule.max_abs_psi_r_rad);
  return why;
}

}  // namespace pensight::global_pose
