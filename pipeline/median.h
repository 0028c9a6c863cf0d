#pragma once
// The median the estimators and tests share: the upper median (element n/2 in sorted order), by
// a partial sort (std::nth_element, linear time); NaN for no values.
#include <algorithm>
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

}  // namespace pensight
