// The median our robust statistics use: the upper median, the element at
// index size/2 of the sorted values (an element of the data, found in linear
// time), NaN for no values.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace uw {

inline double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace uw
