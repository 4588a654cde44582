// levelfuse: the median and quantiles of a set of numbers.
#pragma once

#include <algorithm>
#include <vector>

namespace levelfuse {

/// The median of `values` (the upper one of an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

/// The value below which a fraction `q` (in [0, 1]) of `values` lie: the
/// element at q (n - 1) of them sorted, rounded down; 0 for none.
inline double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace levelfuse
