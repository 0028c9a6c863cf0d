// The hull model (vehicle/hull_dynamics.h) against closed forms: the terminal rise speed of the
// excess buoyancy, steady speeds under a constant force in each axis, the initial acceleration
// F / (m + added mass), righting from a roll, drift with the current, kinetic energy that only
// decays (C is skew-symmetric), RK4 convergence, and the roll-pitch-yaw inverse.
#include <gtest/gtest.h>

#include <cmath>

#include "core/dataset_types.h"
#include "vehicle/hull_dynamics.h"
#include "vehicle/ocean_current.h"
#include "vehicle/vehicle_sim.h"

namespace pensight::vehicle {
namespace {

// The positive root of force = d_lin x + d_quad x^2.
double steady_speed(double force, double d_lin, double d_quad) {
  return (-d_lin + std::sqrt(d_lin * d_lin + 4 * d_quad * force)) / (2 * d_quad);
}

HullParams neutral_hull() {
  HullParams h;
  h.water_density_kgpm3 = h.mass_kg / h.displaced_volume_m3;
  return h;
}

Vector6d along(int axis, double value) {
  Vector6d v = Vector6d::Zero();
  v[axis] = value;
  return v;
}

RigidBodyState run(const HullDynamics& hull, RigidBodyState s, const Vector6d& tau,
                   double duration_s, double dt_s = 0.01,
                   const Eigen::Vector3d& current = Eigen::Vector3d::Zero()) {
  for (int i = 0; i < std::lround(duration_s / dt_s); ++i) s = hull.step(s, tau, current, dt_s);
  return s;
}

RigidBodyState rolled(double roll_deg) {
  RigidBodyState s;
  s.position_pen_m = {0, 0, 5};
  s.q_pen_body = Eigen::Quaterniond(rotation_from_rpy(deg_to_rad(roll_deg), 0, 0));
  return s;
}

TEST(HullDynamics, RisesAtTheTerminalSpeedOfItsExcessBuoyancy) {
  const HullParams h;
  const HullDynamics hull(h);
  const double excess_N = hull.buoyancy_N() - hull.weight_N();
  EXPECT_NEAR(excess_N, 1025 * 0.0134 * 9.81 - 13.5 * 9.81, 1e-9);
  const double expected = steady_speed(excess_N, h.linear_damping[2], h.quadratic_damping[2]);
  // Unpowered in the full simulator: thrusters off, the vehicle floats up at 5.3 cm/s.
  VehicleSim sim({}, rolled(0));
  sim.advance(15);
  EXPECT_NEAR(-sim.velocity_pen_mps().z(), expected, 1e-7);
  EXPECT_NEAR(sim.velocity_pen_mps().head<2>().norm(), 0, 1e-9);
}

TEST(HullDynamics, RightsItselfFromARoll) {
  // Only the centre of buoyancy above the CG levels it; quadratic roll damping shrinks the swing.
  VehicleSim sim({}, rolled(20));
  double early_deg = 0, late_deg = 0;
  for (int i = 0; i < 300; ++i) {
    sim.advance(0.1);
    double& peak_deg = i < 100 ? early_deg : late_deg;
    peak_deg = std::max(peak_deg, std::abs(rad_to_deg(sim.roll_rad())));
  }
  EXPECT_GT(early_deg, 19.0);
  EXPECT_LT(late_deg, 3.0);  // 1.6 deg measured over 10..30 s
}

TEST(HullDynamics, ConstantForceGivesTheSpeedWhereDampingBalancesIt) {
  const HullParams h = neutral_hull();
  const HullDynamics hull(h);
  for (const auto& [axis, force] : {std::pair{0, 20.0}, {1, 20.0}, {2, -20.0}, {5, 2.0}}) {
    const RigidBodyState s = run(hull, {}, along(axis, force), 30);
    const double expected = std::copysign(
        steady_speed(std::abs(force), h.linear_damping[axis], h.quadratic_damping[axis]), force);
    EXPECT_NEAR(s.nu_body[axis], expected, 1e-6 * std::abs(expected)) << "axis " << axis;
  }
}

TEST(HullDynamics, StepForceAcceleratesAgainstRigidAndAddedMass) {
  const HullParams h = neutral_hull();
  const HullDynamics hull(h);
  for (int axis = 0; axis < 6; ++axis) {
    const double inertia = axis < 3 ? h.mass_kg : h.inertia_kgm2[axis - 3];
    const Vector6d a = hull.acceleration({}, along(axis, 10.0), Eigen::Vector3d::Zero());
    EXPECT_NEAR(a[axis], 10.0 / (inertia + h.added_mass[axis]), 1e-12) << "axis " << axis;
    EXPECT_NEAR(a.norm(), std::abs(a[axis]), 1e-12) << "axis " << axis;
  }
}

TEST(HullDynamics, UnpoweredNeutralVehicleDriftsWithTheCurrent) {
  VehicleParams p;
  p.hull = neutral_hull();
  p.current.mean_pen_mps = {0.3, -0.2, 0.0};
  VehicleSim sim(p, rolled(0));
  sim.advance(60);
  // Sway has no linear damping, so the last of the slip decays as 1/t: 1.6 mm/s left at 60 s.
  EXPECT_LT((sim.velocity_pen_mps() - p.current.mean_pen_mps).norm(), 0.005);
  EXPECT_EQ(sim.current_pen_mps(), p.current.mean_pen_mps);
}

TEST(OceanCurrent, VariesAboutTheMeanWithTheSetSpreadAndSeed) {
  CurrentParams c;
  c.mean_pen_mps = {0.1, 0.0, 0.0};
  c.variation_mps = 0.05;
  c.time_constant_s = 5;
  OceanCurrent a(c), b(c);
  c.seed = 99;
  OceanCurrent other(c);
  double sum_sq = 0;
  const int n = 20000;  // 2000 s, 400 time constants
  for (int i = 0; i < n; ++i) {
    a.advance(0.1);
    b.advance(0.1);
    other.advance(0.1);
    sum_sq += (a.velocity_pen_mps() - c.mean_pen_mps).head<2>().squaredNorm() / 2;
    EXPECT_EQ(a.velocity_pen_mps().z(), 0.0);
  }
  EXPECT_NEAR(std::sqrt(sum_sq / n), c.variation_mps, 0.2 * c.variation_mps);
  EXPECT_EQ(a.velocity_pen_mps(), b.velocity_pen_mps());
  EXPECT_NE(a.velocity_pen_mps(), other.velocity_pen_mps());
}

TEST(HullDynamics, KineticEnergyIsKeptByCoriolisAndTakenByDamping) {
  HullParams h = neutral_hull();
  h.cb_body_m.setZero();  // no restoring: all energy is kinetic
  Vector6d mass;
  mass << Eigen::Vector3d::Constant(h.mass_kg), h.inertia_kgm2;
  mass += Eigen::Map<const Vector6d>(h.added_mass.data());
  const auto energy = [&](const RigidBodyState& s) {
    return 0.5 * s.nu_body.dot(mass.cwiseProduct(s.nu_body));
  };
  RigidBodyState start;
  start.nu_body << 1.0, 0.5, -0.3, 0.5, -0.4, 1.0;
  const double start_J = energy(start);

  // Without damping these are Kirchhoff's equations: C(nu) is skew-symmetric, so the energy only
  // moves between the axes, and the impulse p = M v keeps |p| and p . (M w).
  HullParams undamped = h;
  undamped.linear_damping.fill(0);
  undamped.quadratic_damping.fill(0);
  const RigidBodyState coasted = run(HullDynamics(undamped), start, Vector6d::Zero(), 10);
  EXPECT_NEAR(energy(coasted), start_J, 1e-6 * start_J);
  EXPECT_GT((coasted.nu_body - start.nu_body).norm(), 0.1);  // it did exchange
  const Vector6d before = mass.cwiseProduct(start.nu_body);
  const Vector6d after = mass.cwiseProduct(coasted.nu_body);
  const double p_dot_h = before.head<3>().dot(before.tail<3>());
  EXPECT_NEAR(after.head<3>().norm(), before.head<3>().norm(), 1e-6 * before.head<3>().norm());
  EXPECT_NEAR(after.head<3>().dot(after.tail<3>()), p_dot_h, 1e-6 * std::abs(p_dot_h));

  const HullDynamics hull(h);
  RigidBodyState s = start;
  double previous_J = start_J;
  for (int i = 0; i < 2000; ++i) {
    s = hull.step(s, Vector6d::Zero(), Eigen::Vector3d::Zero(), 0.01);
    ASSERT_LT(energy(s), previous_J) << "step " << i;
    previous_J = energy(s);
  }
  EXPECT_LT(previous_J, 0.01 * start_J);
}

TEST(HullDynamics, HalvingTheStepBarelyChangesTenSecondsOfMotion) {
  const HullDynamics hull{HullParams{}};
  RigidBodyState s = rolled(10);
  s.nu_body << 0.5, 0.2, 0.1, 0.3, 0.0, 0.5;
  Vector6d tau;
  tau << 20, 5, -10, 0.5, 0.3, 1.0;
  const RigidBodyState coarse = run(hull, s, tau, 10, 0.01);
  const RigidBodyState fine = run(hull, s, tau, 10, 0.005);
  EXPECT_LT((coarse.position_pen_m - fine.position_pen_m).norm(), 1e-7);  // 1.4e-9 m measured
  EXPECT_LT(coarse.q_pen_body.angularDistance(fine.q_pen_body), 1e-7);
  EXPECT_GT((fine.position_pen_m - s.position_pen_m).norm(), 0.5);  // it went somewhere
}

TEST(HullDynamics, RpyFromRotationInvertsRotationFromRpy) {
  for (const Eigen::Vector3d& rpy :
       {Eigen::Vector3d(0.3, -0.2, 2.5), Eigen::Vector3d(-3.0, 1.4, -0.7),
        Eigen::Vector3d(0.0, 0.0, 3.1)}) {
    EXPECT_LT((rpy_from_rotation(rotation_from_rpy(rpy[0], rpy[1], rpy[2])) - rpy).norm(), 1e-12);
  }
  const Eigen::Vector3d up = rpy_from_rotation(rotation_from_rpy(0, std::numbers::pi / 2, 0.4));
  EXPECT_NEAR(up[1], std::numbers::pi / 2, 1e-7);
  EXPECT_NEAR(up[2], 0.4, 1e-7);
}

}  // namespace
}  // namespace pensight::vehicle
