#pragma once
// Extended Kalman filter of the vehicle's horizontal pose in the pen, its depth, its velocity and
// the offset between the attitude sensor's yaw and the pen frame. The state:
//   x, y [m]      body origin in the pen frame P (rho_g = atan2(y, x), r_g = |(x, y)|)
//   z [m]         depth of the body origin
//   psi [rad]     body yaw in P
//   u, v, w [m/s] body velocity in the levelled frame L (forward, right, down)
//   psi_rate      yaw rate [rad/s]
//   yaw_bias      attitude-sensor yaw minus psi [rad]
//   dvl_bias u, v DVL horizontal velocity error [m/s] (offset, and scale error at steady speed)
//   fix_heading_bias  the vision heading's (circle fit psi_r, FFT psi_net) slowly varying error
//                 [rad]: it comes from the same net points frame after frame, so it is a
//                 first-order Gauss-Markov process, not white noise
//   net_texture_offset [m]  the along-wall coordinate of the net point on the camera's centre
//                 ray minus the net texture odometer's reading (apply_texture in
//                 global_pose_estimator.h): constant but for the odometer's own step errors,
//                 which are added to its variance at each step
// Process: constant velocity in L and constant yaw rate, driven by white acceleration noise; the
// levelled velocity turns with the vehicle (du = r v dt, dv = -r u dt). Measurements are any
// function h(x); Jacobians are taken by central differences (the state is 13 numbers, so this
// costs well under a microsecond per measurement row and keeps models and their Jacobians from
// disagreeing). Every update is gated on its Mahalanobis distance.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "pipeline/global_pose/pen_geometry.h"

namespace pensight::global_pose {

enum StateIndex : int {
  kX,
  kY,
  kZ,
  kPsi,
  kU,
  kV,
  kW,
  kPsiRate,
  kYawBias,
  kDvlBiasU,
  kDvlBiasV,
  kFixHeadingBias,
  kNetTextureOffset,
  kStateDim
};
using StateVector = Eigen::Matrix<double, kStateDim, 1>;
using StateMatrix = Eigen::Matrix<double, kStateDim, kStateDim>;

// Sized for an ROV's manoeuvres (accelerations of ~0.5 m/s^2 and ~0.5 rad/s^2 over a few tenths of
// a second): with 0.05 the filter gated out half the DVL samples and most fixes through the
// sweep's turns and reversals. A 2 m/s DVL spike is still ~8 sigma after a 0.25 s DVL interval.
// The horizontal acceleration is quiet_horizontal_accel where consecutive DVL samples show quiet
// motion (motion_schedule.h): the largest change a quiet span allows, 0.4 m/s^2 over a 0.25 s
// interval, is 2 sigma of it. 0.05 was tighter still on the renders along the net but let the
// geometric flat-net drift reach 0.87 of the published node's (bound 0.8).
struct ProcessNoise {
  double horizontal_accel = 0.5;        // m/s^2 per sqrt(Hz), manoeuvring
  double quiet_horizontal_accel = 0.1;  // m/s^2 per sqrt(Hz), following or holding station
  double vertical_accel = 0.05;         // m/s^2 per sqrt(Hz)
  double yaw_accel = 0.5;               // rad/s^2 per sqrt(Hz)
  double yaw_bias_walk = 1e-4;          // rad per sqrt(s): drift of the attitude sensor's yaw
  double dvl_bias_walk = 3e-5;          // m/s per sqrt(s): a scale error changes with the speed
  // The vision heading error's stationary standard deviation and correlation time. Without it
  // the attitude yaw and ten white fixes a second would pin the azimuth to the fixes' wander
  // (0.2 deg is 4 cm of arc at 12 m) instead of integrating the DVL over short spans.
  double fix_heading_bias_rad = 0.002;
  double fix_heading_bias_time_s = 30.0;
};

// dh/dx at x by central differences over the states in `depends_on` (the other columns are
// zero); rows marked in `angles` wrap at +-pi. Not finite where h is not at a perturbed state.
template <int M, class H>
Eigen::Matrix<double, M, kStateDim> numeric_jacobian(const StateVector& x, H&& h,
                                                     std::span<const int> depends_on,
                                                     std::array<bool, M> angles) {
  Eigen::Matrix<double, M, kStateDim> J = Eigen::Matrix<double, M, kStateDim>::Zero();
  for (const int j : depends_on) {
    const double step = 1e-6 * std::max(1.0, std::abs(x(j)));
    StateVector xp = x, xm = x;
    xp(j) += step;
    xm(j) -= step;
    Eigen::Matrix<double, M, 1> diff = h(xp) - h(xm);
    for (int i = 0; i < M; ++i)
      if (angles[static_cast<size_t>(i)]) diff(i) = wrap_angle(diff(i));
    J.col(j) = diff / (2 * step);
  }
  return J;
}

// Chi-square quantiles at p = 0.999 for 1, 2 and 3 degrees of freedom.
inline constexpr double kGateChi2[4] = {0.0, 10.83, 13.82, 16.27};

enum class UpdateOutcome { kAccepted, kRejected, kSkipped };

struct PenEkf {
  StateVector x = StateVector::Zero();
  StateMatrix P = StateMatrix::Identity();
  int64_t t_ns = 0;

  static StateVector propagate(const StateVector& x, double dt);
  // Advances to t_ns (sub-steps of at most 50 ms); a negative interval extrapolates backwards
  // with the process noise of its length.
  void predict_to(int64_t t_new_ns, const ProcessNoise& q);

  // z ~ h(x) + N(0, R). `angles` marks rows whose innovation wraps at +-pi; h depends only on the
  // states listed in `depends_on` (the others' Jacobian columns are zero and not evaluated). The
  // update is rejected when the innovation's squared Mahalanobis distance exceeds gate_chi2
  // (<= 0: no gate).
  template <int M, class H>
  UpdateOutcome update(const Eigen::Matrix<double, M, 1>& z, H&& h,
                       const Eigen::Matrix<double, M, M>& R, std::array<bool, M> angles,
                       std::span<const int> depends_on, double gate_chi2);
};

template <int M, class H>
UpdateOutcome PenEkf::update(const Eigen::Matrix<double, M, 1>& z, H&& h,
                             const Eigen::Matrix<double, M, M>& R, std::array<bool, M> angles,
                             std::span<const int> depends_on, double gate_chi2) {
  using Vec = Eigen::Matrix<double, M, 1>;
  const Vec hx = h(x);
  if (!hx.allFinite() || !z.allFinite()) return UpdateOutcome::kSkipped;
  const Eigen::Matrix<double, M, kStateDim> H_ = numeric_jacobian<M>(x, h, depends_on, angles);
  if (!H_.allFinite()) return UpdateOutcome::kSkipped;
  Vec nu = z - hx;
  for (int i = 0; i < M; ++i)
    if (angles[static_cast<size_t>(i)]) nu(i) = wrap_angle(nu(i));
  const Eigen::Matrix<double, M, kStateDim> HP = H_.lazyProduct(P);
  const Eigen::Matrix<double, M, M> S = HP.lazyProduct(H_.transpose()) + R;
  const Eigen::LDLT<Eigen::Matrix<double, M, M>> ldlt(S);
  if (ldlt.info() != Eigen::Success) return UpdateOutcome::kSkipped;
  const double m2 = nu.dot(ldlt.solve(nu));
  if (gate_chi2 > 0 && !(m2 <= gate_chi2)) return UpdateOutcome::kRejected;
  const Eigen::Matrix<double, kStateDim, M> K = ldlt.solve(HP).transpose();
  x += K * nu;
  x(kPsi) = wrap_angle(x(kPsi));
  x(kYawBias) = wrap_angle(x(kYawBias));
  // P - K H P (rank M), symmetrised; the Joseph form costs two more 11x11 products and buys
  // nothing measurable with gated, well-conditioned updates.
  P -= K.lazyProduct(HP);
  P = 0.5 * (P + P.transpose()).eval();
  return UpdateOutcome::kAccepted;
}

}  // namespace pensight::global_pose
