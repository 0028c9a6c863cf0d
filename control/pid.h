#pragma once
// A PID loop with the three guards a thruster command needs: output saturation, anti-windup and a
// rate limit (docs/control.md). Discrete, parallel form, u = Kp e + Ki sum(e dt) + Kd de/dt, run
// at the caller's rate with the step passed in (no clock of its own).
#include <limits>

#include "core/units.h"

namespace pensight::control {

struct PidGains {
  double kp = 0, ki = 0, kd = 0;
};

struct PidLimits {
  double output_max = std::numeric_limits<double>::infinity();  // |u| <= output_max
  // Output change per second; infinity: none. A step in the reference then ramps instead of
  // kicking the thrusters.
  double rate_max = std::numeric_limits<double>::infinity();
};

class Pid {
 public:
  Pid() = default;
  Pid(PidGains gains, PidLimits limits) : gains_(gains), limits_(limits) {}

  // One step of `dt_s` > 0 with error e = reference - measurement. `error_rate` is de/dt when the
  // caller measures it (a DVL velocity, a gyro); NaN: the difference of successive errors, which
  // the first step after reset() leaves out (no derivative kick). A NaN error returns the last
  // output and leaves the state alone.
  // Anti-windup by conditional integration: the integral does not grow while the output is
  // saturated in the error's direction, and Ki * integral alone never exceeds output_max.
  double update(double error, double dt_s, double error_rate = kNaN);
  // Forgets the integral, the last error and the last output (a new mode starts from rest).
  void reset();
  // Bumpless transfer: sets the integral so that its term alone is `output` (clamped like
  // update()), e.g. the force another mode held a disturbance with. No effect when Ki is 0.
  void set_integral_term(double output);
  double output() const { return output_; }
  double integral() const { return integral_; }
  const PidGains& gains() const { return gains_; }

 private:
  PidGains gains_;
  PidLimits limits_;
  double integral_ = 0, last_error_ = 0, output_ = 0;
  bool has_last_ = false;
};

}  // namespace pensight::control
