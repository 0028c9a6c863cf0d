#include "control/pid.h"

#include <algorithm>
#include <cmath>

namespace pensight::control {

double Pid::update(double error, double dt_s, double error_rate) {
  if (!std::isfinite(error) || !(dt_s > 0)) return output_;
  double derivative = 0;
  if (std::isfinite(error_rate)) {
    derivative = error_rate;
  } else if (has_last_) {
    derivative = (error - last_error_) / dt_s;
  }
  last_error_ = error;
  has_last_ = true;

  const double unsaturated_no_i = gains_.kp * error + gains_.kd * derivative;
  const double candidate = integral_ + error * dt_s;
  const double with_i = unsaturated_no_i + gains_.ki * candidate;
  // Integrate only when that does not push a saturated output further out.
  const bool saturating = std::abs(with_i) > limits_.output_max && with_i * error > 0;
  if (!saturating && gains_.ki > 0) {
    integral_ = candidate;
    const double i_max = limits_.output_max / gains_.ki;
    integral_ = std::clamp(integral_, -i_max, i_max);
  }
  double u = unsaturated_no_i + gains_.ki * integral_;
  u = std::clamp(u, -limits_.output_max, limits_.output_max);
  if (std::isfinite(limits_.rate_max)) {
    const double step = limits_.rate_max * dt_s;
    u = std::clamp(u, output_ - step, output_ + step);
  }
  output_ = u;
  return u;
}

void Pid::set_integral_term(double output) {
  if (!(gains_.ki > 0) || !std::isfinite(output)) return;
  const double i_max = limits_.output_max / gains_.ki;
  integral_ = std::clamp(output / gains_.ki, -i_max, i_max);
}

void Pid::reset() {
  integral_ = 0;
  last_error_ = 0;
  output_ = 0;
  has_last_ = false;
}

}  // namespace pensight::control
