// Order statistics of timing samples for the benchmarks (medians, not means: the machine is
// shared and noisy, and a median ignores the occasional descheduled frame).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace ring_curvature
{
namespace bench
{

/// Value at quantile q in [0, 1] (nearest rank); NaN for no samples. Takes a copy on purpose.
inline double quantile(std::vector<double> v, double q)
{
  if (v.empty())
    return std::nan("");
  const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

inline double median(const std::vector<double>& v) { return quantile(v, 0.5); }

}  // namespace bench
}  // namespace ring_curvature
