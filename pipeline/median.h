#pragma once
// The median the estimators and tests share: the upper median (element n/2 in sorted order), by
// a partial sort (std::nth_element, linear time); NaN for no values.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "runtime/units.h"

namespace pensight {

inline double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// A median's standard error is sqrt(pi / 2) times a mean's (normal data, many samples).
inline constexpr double kMedianErrorOverMeanError = 1.2533;

// A window's median and its standard error, robust to outliers: 1.4826 MAD is the standard
// deviation of normal data. NaN for no values.
struct MedianWithError {
  double median = kNaN, standard_error = kNaN;
};
inline MedianWithError median_with_error(const std::vector<double>& values) {
  const double m = median(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (double v : values) deviations.push_back(std::abs(v - m));
  return {m, kMedianErrorOverMeanError * 1.4826 * median(std::move(deviations)) /
                 std::sqrt(static_cast<double>(values.size()))};
}

}  // namespace pensight
