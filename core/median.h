#pragma once
// The median the estimators and tests share: the upper median (element n/2 in sorted order), by
// a partial sort (std::nth_element, linear time); NaN for no values.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/units.h"

namespace pensight {

inline double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// A median's standard error is sqrt(pi / 2) times a mean's (normal data, many samples).
inline constexpr double kMedianErrorOverMeanError = 1.2533;

// The standard deviation of normal data is 1.4826 times its median absolute deviation (MAD): the
// robust sigma is kMadToSigma * MAD.
inline constexpr double kMadToSigma = 1.4826;

// A window's median and its standard error, robust to outliers: kMadToSigma MAD is the standard
// deviation of normal data. NaN for no values.
struct MedianWithError {
  double median = kNaN, standard_error = kNaN;
};
inline MedianWithError median_with_error(const std::vector<double>& values) {
  const double m = median(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (double v : values) deviations.push_back(std::abs(v - m));
  return {m, kMedianErrorOverMeanError * kMadToSigma * median(std::move(deviations)) /
                 std::sqrt(static_cast<double>(values.size()))};
}

}  // namespace pensight
