// GlobalPoseEstimator, part 3 of 4: re-locking after rejections in a row (the gate itself,
// gated_update, is in estimator_detail.h, as every sensor model instantiates it).
#include "pipeline/global_pose/global_pose_estimator.h"

#include <cmath>
#include <cstdio>
#include <span>

#include "core/log.h"

#include "pipeline/global_pose/estimator_detail.h"

namespace pensight::global_pose {
using namespace detail;

void GlobalPoseEstimator::release_motion_states(int sensor) {
  struct Release {
    int state;
    double sigma;
  };
  const FilterPriors& p = cfg_.priors;
  const Release dvl_motion[] = {
      {kU, p.released_velocity_mps}, {kV, p.released_velocity_mps}, {kW, p.released_velocity_mps}};
  const Release yaw_motion[] = {{kPsi, p.released_heading_rad},
                                {kPsiRate, p.released_psi_rate_radps}};
  const Release depth_motion[] = {{kZ, p.released_depth_m}, {kW, p.released_velocity_mps}};
  StateMatrix& P = state_.ekf.P;
  std::span<const Release> released = depth_motion;
  if (sensor == kDvlVelocity) released = dvl_motion;
  if (sensor == kAttitudeYaw) released = yaw_motion;
  for (const Release& r : released) {
    P.row(r.state).setZero();
    P.col(r.state).setZero();
    P(r.state, r.state) = r.sigma * r.sigma;
  }
}

void GlobalPoseEstimator::consider_reinitialising(const PenFix& fix,
                                                  const Eigen::Vector2d& innovation, int64_t t_ns) {
  auto& run = state_.rejected_fixes;
  const size_t needed = static_cast<size_t>(std::max(0, cfg_.lock.reinit_after_rejected_fixes));
  const double rho = std::atan2(state_.ekf.x(kY), state_.ekf.x(kX));
  if (needed < 2 || !check_lock_at(fix, rho, t_ns).lockable()) {
    run.clear();
    return;
  }
  run.push_back({t_ns, innovation});
  if (run.size() > needed) run.erase(run.begin());
  if (run.size() < needed) return;
  // The fixes agree when their innovations lie on a line in time: a constant offset (the filter's
  // position is wrong) plus a constant rate (its velocity is wrong too, e.g. after a reversal the
  // constant-velocity model did not expect).
  double t_mean = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    t_mean += seconds_between(t_ns, f.t_ns);
    mean += f.innovation;
  }
  t_mean /= static_cast<double>(run.size());
  mean /= static_cast<double>(run.size());
  double stt = 0;
  Eigen::Vector2d sty = Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    const double dt = seconds_between(t_ns, f.t_ns) - t_mean;
    stt += dt * dt;
    sty += dt * (f.innovation - mean);
  }
  const Eigen::Vector2d rate = stt > 0 ? Eigen::Vector2d(sty / stt) : Eigen::Vector2d::Zero();
  for (const auto& f : run) {
    const double dt = seconds_between(t_ns, f.t_ns) - t_mean;
    const Eigen::Vector2d residual = f.innovation - mean - dt * rate;
    if (std::abs(residual.x()) > cfg_.lock.agree_r_m ||
        std::abs(residual.y()) > cfg_.lock.agree_psi_r_rad)
      return;
  }
  char buf[240];
  std::snprintf(
      buf, sizeof(buf),
      "global pose: %zu vision fixes in a row gated out but agreeing (distance to the net "
      "off by %.2f m changing %.2f m/s, heading by %.1f deg): position re-initialised at "
      "t = %lld ns",
      run.size(), innovation.x(), rate.x(), rad_to_deg(innovation.y()),
      static_cast<long long>(t_ns));
  log_warning(buf);
  reinitialise_position(fix, rate.x(), t_ns);
  ++state_.counts.vision_fix.reinitialised;
  run.clear();
}

}  // namespace pensight::global_pose
