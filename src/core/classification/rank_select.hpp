// Exact selection of a rank among floats in O(n) (never a sort): the thresholds' general path.
#pragma once

#include <algorithm>
#include <cstddef>

namespace ring_curvature
{

/// Value at quantile q of v[0..n) by O(n) selection (v is reordered). NaN when n == 0.
float selectQuantile(float* v, std::size_t n, double q);
/// Value of rank k (0-based, k < n) of v[0..n) by the same selection (v is reordered, never
/// overwritten).
float selectNth(float* v, std::size_t n, std::size_t k);

namespace detail
{
/// Nearest rank of quantile q of n values: floor(q * (n - 1)).
inline std::size_t rankOf(std::size_t n, double q)
{
  return std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n - 1)));
}
}  // namespace detail

}  // namespace ring_curvature
