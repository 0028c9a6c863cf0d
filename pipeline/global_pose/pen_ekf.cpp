#include "pipeline/global_pose/pen_ekf.h"

#include <algorithm>
#include <cmath>

namespace pensight::global_pose {

StateVector PenEkf::propagate(const StateVector& s, double dt) {
  StateVector n = s;
  const double c = std::cos(s(kPsi)), si = std::sin(s(kPsi));
  n(kX) += dt * (c * s(kU) - si * s(kV));
  n(kY) += dt * (si * s(kU) + c * s(kV));
  n(kZ) += dt * s(kW);
  n(kPsi) = wrap_angle(s(kPsi) + dt * s(kPsiRate));
  n(kU) += dt * s(kPsiRate) * s(kV);
  n(kV) -= dt * s(kPsiRate) * s(kU);
  return n;
}

void PenEkf::predict_to(int64_t t_new_ns, const ProcessNoise& q) {
  double remaining = seconds_between(t_ns, t_new_ns);
  t_ns = t_new_ns;
  while (remaining != 0.0) {
    const double dt = std::clamp(remaining, -0.05, 0.05);
    remaining = std::abs(remaining) <= 0.05 ? 0.0 : remaining - dt;
    const double c = std::cos(x(kPsi)), si = std::sin(x(kPsi));
    StateMatrix F = StateMatrix::Identity();
    F(kX, kPsi) = dt * (-si * x(kU) - c * x(kV));
    F(kX, kU) = dt * c;
    F(kX, kV) = -dt * si;
    F(kY, kPsi) = dt * (c * x(kU) - si * x(kV));
    F(kY, kU) = dt * si;
    F(kY, kV) = dt * c;
    F(kZ, kW) = dt;
    F(kPsi, kPsiRate) = dt;
    F(kU, kV) = dt * x(kPsiRate);
    F(kU, kPsiRate) = dt * x(kV);
    F(kV, kU) = -dt * x(kPsiRate);
    F(kV, kPsiRate) = -dt * x(kU);
    x = propagate(x, dt);
    const double a = std::abs(dt);
    const double decay = std::exp(-a / q.fix_heading_bias_time_s);
    F(kFixHeadingBias, kFixHeadingBias) = decay;
    x(kFixHeadingBias) *= decay;
    StateMatrix Q = StateMatrix::Zero();
    Q(kU, kU) = Q(kV, kV) = q.horizontal_accel * q.horizontal_accel * a;
    Q(kW, kW) = q.vertical_accel * q.vertical_accel * a;
    Q(kPsiRate, kPsiRate) = q.yaw_accel * q.yaw_accel * a;
    Q(kYawBias, kYawBias) = q.yaw_bias_walk * q.yaw_bias_walk * a;
    Q(kDvlBiasU, kDvlBiasU) = Q(kDvlBiasV, kDvlBiasV) = q.dvl_bias_walk * q.dvl_bias_walk * a;
    Q(kFixHeadingBias, kFixHeadingBias) =
        q.fix_heading_bias_rad * q.fix_heading_bias_rad * (1 - decay * decay);
    // Coefficient-based products: for 11x11 Eigen's blocked GEMM path costs several times more.
    const StateMatrix FP = F.lazyProduct(P);
    P = FP.lazyProduct(F.transpose()) + Q;
  }
}

}  // namespace pensight::global_pose
