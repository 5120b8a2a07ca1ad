// Mean and population standard deviation of a sample (NaN when it is empty).
#pragma once

#include <cmath>
#include <vector>

namespace rlt {

inline double mean_of(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += x;
  return v.empty() ? NAN : s / double(v.size());
}

inline double std_of(const std::vector<float>& v) {
  if (v.empty()) return NAN;
  const double m = mean_of(v);
  double s = 0;
  for (float x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size()));
}

}  // namespace rlt
