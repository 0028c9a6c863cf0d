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

// Nanoseconds to seconds. Exact to 1 ns over 104 days (the span a double holds in ns).
constexpr double ns_to_seconds(int64_t ns) {
  return 1e-9 * static_cast<double>(ns);
}

// to_ns - from_ns in seconds, as ns_to_seconds.
constexpr double seconds_between(int64_t from_ns, int64_t to_ns) {
  return ns_to_seconds(to_ns - from_ns);
}

// Seconds to integer nanoseconds: s * 1e9 (in double) rounded to the nearest, halves away from
// zero, as std::llround. |s| must stay below 292 years (int64 nanoseconds).
constexpr int64_t seconds_to_ns(double s) {
  const double ns = s * 1e9;
  const auto whole = static_cast<int64_t>(ns);              // toward zero
  const double fraction = ns - static_cast<double>(whole);  // exact: below 1 in magnitude
  return whole + (fraction >= 0.5 ? 1 : fraction <= -0.5 ? -1 : 0);
}

// Seconds to integer nanoseconds rounded toward zero: the window lengths and gaps of the depth
// and global-pose estimators. It differs from seconds_to_ns where s * 1e9 falls just below an
// integer in double: 4.1 s is 4099999999 ns here, 4100000000 ns there.
constexpr int64_t seconds_to_ns_toward_zero(double s) {
  return static_cast<int64_t>(s * 1e9);
}

}  // namespace pensight
