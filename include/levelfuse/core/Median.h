// levelfuse: the median of a set of numbers.
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

}  // namespace levelfuse
