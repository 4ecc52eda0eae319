// Radix selection of a rank among floats (see rank_select.hpp).
#include "classification/rank_select.hpp"
#include "common/float_bits.hpp"

#include <cstdint>
#include <limits>

namespace ring_curvature
{

using detail::orderedKey;
using detail::rankOf;

float selectNth(float* v, std::size_t n, std::size_t k)
{
  // Radix selection, most significant digit first (nth_element's element without its unpredictable
  // comparisons). Digits start at the highest bit in which the keys differ, as a selection's values
  // often share sign, exponent and leading bits. Never overwrites: callers reuse all n values.
  std::size_t m = n;
  float* c = v;
  if (m <= 32)
  {
    std::nth_element(c, c + k, c + m);
    return c[k];
  }
  std::uint32_t lo = 0xFFFFFFFFu, hi = 0;
  for (std::size_t i = 0; i < m; ++i)
  {
    const std::uint32_t key = orderedKey(c[i]);
    lo = std::min(lo, key);
    hi = std::max(hi, key);
  }
  if (lo == hi) return c[k];  // one key: every value is the same float
  int top = 31;               // highest bit still undecided
  while (((lo ^ hi) >> top) == 0) --top;
  constexpr int kDigit = 11;
  // Two histograms, for even and odd positions: runs of equal digits (the common case) would
  // otherwise chain every increment to the store of the one before.
  std::uint32_t counts[1u << kDigit], counts_odd[1u << kDigit];
  // Candidates after the first narrowing, when they fit (one past the last so that the
  // branch-free copy below may write one slot beyond the candidates).
  constexpr std::size_t kLocal = 4095;
  float local[kLocal + 1];
  while (m > 32)
  {
    // Digit width from the candidate count: few values should not clear and scan 2 x 2048 counters.
    int digit = 6;
    while (digit < kDigit && (std::size_t{1} << (digit + 2)) <= m) ++digit;
    const int sh = std::max(0, top + 1 - digit);
    const std::uint32_t mask = (1u << (top + 1 - sh)) - 1u;
    std::fill(counts, counts + mask + 1, 0u);
    std::fill(counts_odd, counts_odd + mask + 1, 0u);
    std::size_t i2 = 0;
    for (; i2 + 1 < m; i2 += 2)
    {
      ++counts[(orderedKey(c[i2]) >> sh) & mask];
      ++counts_odd[(orderedKey(c[i2 + 1]) >> sh) & mask];
    }
    if (i2 < m) ++counts[(orderedKey(c[i2]) >> sh) & mask];
    for (std::uint32_t d = 0; d <= mask; ++d) counts[d] += counts_odd[d];
    std::uint32_t bucket = 0;
    std::size_t below = 0;
    while (below + counts[bucket] <= k) below += counts[bucket++];
    k -= below;
    if (counts[bucket] != m && c == v && counts[bucket] <= kLocal)
    {
      // First narrowing: copy the candidates out to a local buffer rather than swap them to the
      // front (a load and a store per value, not two of each); the caller's values stay untouched.
      std::size_t j = 0;
      for (std::size_t i = 0; i < m; ++i)
      {
        const bool in = ((orderedKey(c[i]) >> sh) & mask) == bucket;
        local[j] = c[i];  // [j] is overwritten by the next candidate unless this one is in
        j += in ? 1 : 0;
      }
      c = local;
      m = counts[bucket];
    }
    else if (counts[bucket] != m)  // else every candidate is in it: nothing to move
    {
      std::size_t j = 0;
      for (std::size_t i = 0; i < m; ++i)
      {
        // branch-free partition: [j, i) holds non-members, so swapping a non-member is harmless
        const bool in = ((orderedKey(c[i]) >> sh) & mask) == bucket;
        std::swap(c[i], c[j]);
        j += in ? 1 : 0;
      }
      m = counts[bucket];
    }
    if (sh == 0) return c[k];  // every candidate left has the same key
    top = sh - 1;
  }
  std::nth_element(c, c + k, c + m);
  return c[k];
}

float selectQuantile(float* v, std::size_t n, double q)
{
  return n == 0 ? std::numeric_limits<float>::quiet_NaN() : selectNth(v, n, rankOf(n, q));
}

}  // namespace ring_curvature
