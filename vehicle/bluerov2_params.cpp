#include "vehicle/bluerov2_params.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.h"

namespace pensight::vehicle {
namespace {

void require(bool ok, const std::string& name, const char* rule, double value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "vehicle parameter " << name << " must be " << rule << " (is " << value << ")";
  throw Error(msg.str());
}

// name[i]; appends only, which GCC 12's -Wrestrict does not misread as it does a prefix insert.
std::string indexed(const std::string& name, int i) {
  return name + "[" + std::to_string(i) + "]";
}

void positive(double v, const std::string& name) {
  require(std::isfinite(v) && v > 0, name, "finite and > 0", v);
}

void non_negative(double v, const std::string& name) {
  require(std::isfinite(v) && v >= 0, name, "finite and >= 0", v);
}

void finite(const Eigen::Vector3d& v, const std::string& name) {
  for (int i = 0; i < 3; ++i) {
    require(std::isfinite(v[i]), indexed(name, i), "finite", v[i]);
  }
}

void pid(const PidGains& g, const std::string& name) {
  non_negative(g.p, name + ".p");
  non_negative(g.i, name + ".i");
  non_negative(g.d, name + ".d");
  non_negative(g.imax, name + ".imax");
  non_negative(g.filter_hz, name + ".filter_hz");
}

void check_hull(const HullParams& h) {
  positive(h.mass_kg, "hull.mass_kg");
  positive(h.displaced_volume_m3, "hull.displaced_volume_m3");
  positive(h.water_density_kgpm3, "hull.water_density_kgpm3");
  positive(h.gravity_mps2, "hull.gravity_mps2");
  for (int i = 0; i < 3; ++i) positive(h.inertia_kgm2[i], indexed("hull.inertia_kgm2", i));
  finite(h.cb_body_m, "hull.cb_body_m");
  for (int i = 0; i < 6; ++i) {
    non_negative(h.added_mass[i], indexed("hull.added_mass", i));
    non_negative(h.linear_damping[i], indexed("hull.linear_damping", i));
    non_negative(h.quadratic_damping[i], indexed("hull.quadratic_damping", i));
  }
}

void check_t200(const T200Params& t) {
  positive(t.pwm_min_us, "t200.pwm_min_us");
  require(std::isfinite(t.deadband_low_us) && t.deadband_low_us > t.pwm_min_us,
          "t200.deadband_low_us", "finite and > pwm_min_us", t.deadband_low_us);
  require(std::isfinite(t.deadband_high_us) && t.deadband_high_us >= t.deadband_low_us,
          "t200.deadband_high_us", "finite and >= deadband_low_us", t.deadband_high_us);
  require(std::isfinite(t.pwm_max_us) && t.pwm_max_us > t.deadband_high_us, "t200.pwm_max_us",
          "finite and > deadband_high_us", t.pwm_max_us);
  positive(t.max_forward_N, "t200.max_forward_N");
  positive(t.max_reverse_N, "t200.max_reverse_N");
  positive(t.curve_exponent, "t200.curve_exponent");
  non_negative(t.time_constant_s, "t200.time_constant_s");
}

void check_autopilot(const AutopilotParams& a) {
  positive(a.rate_hz, "autopilot.rate_hz");
  require(std::isfinite(a.pilot_gain) && a.pilot_gain > 0 && a.pilot_gain <= 1,
          "autopilot.pilot_gain", "in (0, 1]", a.pilot_gain);
  positive(a.max_yaw_rate_radps, "autopilot.max_yaw_rate_radps");
  positive(a.max_climb_rate_mps, "autopilot.max_climb_rate_mps");
  require(std::isfinite(a.throttle_deadzone) && a.throttle_deadzone >= 0 && a.throttle_deadzone < 1,
          "autopilot.throttle_deadzone", "in [0, 1)", a.throttle_deadzone);
  non_negative(a.angle_p, "autopilot.angle_p");
  pid(a.rate_roll_pitch, "autopilot.rate_roll_pitch");
  pid(a.rate_yaw, "autopilot.rate_yaw");
  non_negative(a.depth_p, "autopilot.depth_p");
  pid(a.climb_rate, "autopilot.climb_rate");
  non_negative(a.attitude_noise_rad, "autopilot.attitude_noise_rad");
  non_negative(a.depth_noise_m, "autopilot.depth_noise_m");
}

}  // namespace

ThrusterLayout bluerov2_heavy_layout() {
  const double c = std::numbers::sqrt2 / 2;
  const Eigen::Vector3d down = Eigen::Vector3d::UnitZ();
  return {{{{0.156, 0.111, 0.085}, {-c, c, 0}},
           {{0.156, -0.111, 0.085}, {-c, -c, 0}},
           {{-0.156, 0.111, 0.085}, {c, c, 0}},
           {{-0.156, -0.111, 0.085}, {c, -c, 0}},
           {{0.120, 0.218, 0.0}, down},
           {{0.120, -0.218, 0.0}, down},
           {{-0.120, 0.218, 0.0}, down},
           {{-0.120, -0.218, 0.0}, down}}};
}

void check_params(const VehicleParams& p) {
  check_hull(p.hull);
  for (int i = 0; i < kThrusterCount; ++i) {
    const std::string name = indexed("thrusters", i);
    finite(p.thrusters[i].position_body_m, name + ".position_body_m");
    const double norm = p.thrusters[i].direction_body.norm();
    require(std::abs(norm - 1) < 1e-6, name + ".direction_body", "a unit vector; its norm", norm);
  }
  check_t200(p.t200);
  finite(p.current.mean_pen_mps, "current.mean_pen_mps");
  non_negative(p.current.variation_mps, "current.variation_mps");
  positive(p.current.time_constant_s, "current.time_constant_s");
  check_autopilot(p.autopilot);
  positive(p.physics_rate_hz, "physics_rate_hz");
  const double ratio = p.physics_rate_hz / p.autopilot.rate_hz;
  require(ratio >= 1 && std::abs(ratio - std::round(ratio)) < 1e-9 * ratio, "physics_rate_hz",
          "a whole multiple of autopilot.rate_hz", p.physics_rate_hz);
}

}  // namespace pensight::vehicle
