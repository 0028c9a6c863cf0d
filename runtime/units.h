#pragma once
// Units and their conversions, one helper per concept (docs/conventions.md): angles in radians
// wrapped to (-pi, pi], timestamps in integer nanoseconds, NaN for a value that is not known.
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace pensight {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr double deg_to_rad(double deg) {
  return deg * (std::numbers::pi / 180.0);
}
constexpr double rad_to_deg(double rad) {
  return rad * (180.0 / std::numbers::pi);
}

// Into (-pi, pi]. NaN and infinities pass through: an angle that is not known stays not known.
inline double wrap_angle(double a_rad) {
  if (!std::isfinite(a_rad)) return a_rad;
  const double w = std::remainder(a_rad, 2 * std::numbers::pi);
  return w <= -std::numbers::pi ? w + 2 * std::numbers::pi : w;
}

// to_ns - from_ns in seconds. Exact to 1 ns over 104 days (the span a double holds in ns).
constexpr double seconds_between(int64_t from_ns, int64_t to_ns) {
  return 1e-9 * static_cast<double>(to_ns - from_ns);
}

}  // namespace pensight
