// The median of a list of values, found in place (the list is reordered): the upper median, the
// element at index n / 2 of the sorted list, so an even count gives the larger of the middle two.
// 0 for an empty list.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ale {

inline double median_in_place(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace ale
