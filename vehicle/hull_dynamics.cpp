#include "vehicle/hull_dynamics.h"

#include <algorithm>
#include <cmath>

namespace pensight::vehicle {
namespace {

Vector6d to_vector(const std::array<double, 6>& a) {
  return Eigen::Map<const Vector6d>(a.data());
}

// Time derivative of the state.
struct StateRate {
  Eigen::Vector3d position;
  Eigen::Vector4d quaternion;
  Vector6d nu;
};

RigidBodyState advanced(const RigidBodyState& s, const StateRate& k, double h) {
  RigidBodyState out;
  out.position_pen_m = s.position_pen_m + h * k.position;
  out.q_pen_body.coeffs() = s.q_pen_body.coeffs() + h * k.quaternion;
  out.q_pen_body.normalize();
  out.nu_body = s.nu_body + h * k.nu;
  return out;
}

}  // namespace

HullDynamics::HullDynamics(const HullParams& hull)
    : hull_(hull),
      weight_N_(hull.mass_kg * hull.gravity_mps2),
      buoyancy_N_(hull.water_density_kgpm3 * hull.displaced_volume_m3 * hull.gravity_mps2) {
  Vector6d rigid;
  rigid << Eigen::Vector3d::Constant(hull.mass_kg), hull.inertia_kgm2;
  mass_inv_ = (rigid + to_vector(hull.added_mass)).cwiseInverse();
}

Vector6d HullDynamics::acceleration(const RigidBodyState& s, const Vector6d& tau_body,
                                    const Eigen::Vector3d& current_pen_mps) const {
  const Eigen::Matrix3d R = s.q_pen_body.toRotationMatrix();
  const Eigen::Vector3d current_body = R.transpose() * current_pen_mps;
  const Eigen::Vector3d v_r = s.nu_body.head<3>() - current_body;
  const Eigen::Vector3d w = s.nu_body.tail<3>();
  const Vector6d added = to_vector(hull_.added_mass);
  const Eigen::Vector3d added_v = added.head<3>().cwiseProduct(v_r);
  const Eigen::Vector3d added_w = added.tail<3>().cwiseProduct(w);

  Vector6d coriolis;  // C_RB(nu_r) nu_r + C_A(nu_r) nu_r; the A-terms include the Munk moment
  coriolis << hull_.mass_kg * w.cross(v_r) + w.cross(added_v),
      w.cross(hull_.inertia_kgm2.cwiseProduct(w)) + v_r.cross(added_v) + w.cross(added_w);

  Vector6d nu_r;
  nu_r << v_r, w;
  const Vector6d damping = (to_vector(hull_.linear_damping) +
                            to_vector(hull_.quadratic_damping).cwiseProduct(nu_r.cwiseAbs()))
                               .cwiseProduct(nu_r);

  // -g(eta): weight down at the CG (the origin), buoyancy up at the CB.
  const Eigen::Vector3d down_body = R.row(2).transpose();
  Vector6d restoring;
  restoring << (weight_N_ - buoyancy_N_) * down_body,
      hull_.cb_body_m.cross(-buoyancy_N_ * down_body);

  Vector6d nu_dot = mass_inv_.cwiseProduct(tau_body - coriolis - damping + restoring);
  // nu = nu_r + [R^T v_c; 0], and R^T v_c turns with the body: d/dt (R^T v_c) = -w x R^T v_c.
  nu_dot.head<3>() -= w.cross(current_body);
  return nu_dot;
}

RigidBodyState HullDynamics::step(const RigidBodyState& s, const Vector6d& tau_body,
                                  const Eigen::Vector3d& current_pen_mps, double dt_s) const {
  const auto rate = [&](const RigidBodyState& x) {
    const Eigen::Vector3d w = x.nu_body.tail<3>();
    StateRate k;
    k.position = x.q_pen_body * x.nu_body.head<3>();
    k.quaternion = 0.5 * (x.q_pen_body * Eigen::Quaterniond(0, w.x(), w.y(), w.z())).coeffs();
    k.nu = acceleration(x, tau_body, current_pen_mps);
    return k;
  };
  const StateRate k1 = rate(s);
  const StateRate k2 = rate(advanced(s, k1, dt_s / 2));
  const StateRate k3 = rate(advanced(s, k2, dt_s / 2));
  const StateRate k4 = rate(advanced(s, k3, dt_s));
  StateRate sum;
  sum.position = k1.position + 2 * k2.position + 2 * k3.position + k4.position;
  sum.quaternion = k1.quaternion + 2 * k2.quaternion + 2 * k3.quaternion + k4.quaternion;
  sum.nu = k1.nu + 2 * k2.nu + 2 * k3.nu + k4.nu;
  return advanced(s, sum, dt_s / 6);
}

}  // namespace pensight::vehicle
