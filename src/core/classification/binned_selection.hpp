// Selection of a ring's quartiles and of its median + k MAD from a histogram of the values'
// bits, with only the values of the wanted bins copied out for the exact selection.
#pragma once

#include "ring_curvature/scan_grid.hpp"
#include "common/float_bits.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

constexpr float kMadToSigma = 1.4826f;  // MAD of a normal distribution is 0.6745 sigma

// Ring features are non-negative (NaN where undefined), and a non-negative float's bits order like
// it: bits >> 20 (exponent and three mantissa bits, eighths of a binade) bin the values in place,
// with no key transform; only the wanted bins' values are copied out for the exact selection.
constexpr int kBinShift = 20;  // finer bins mean longer bound walks
constexpr std::uint32_t kBins = 1u << (31 - kBinShift);          // every float with a clear sign bit
constexpr std::uint32_t kFiniteBins = 0x7F800000u >> kBinShift;  // the rest: +inf and NaN (exponent all ones)
inline float lowEdge(std::uint32_t bin) { return bitsFloat(bin << kBinShift); }
inline float highEdge(std::uint32_t bin) { return bitsFloat(((bin + 1) << kBinShift) - 1); }

// One ring's counts per bin. Between rings every counter is zero: a ring clears only the bins its
// values can fall in (+0's, [lowest, highest], the non-finite), not the whole histogram.
struct BinnedRing
{
  float* cand;  // the wanted values (n + 8: the vector copy stores whole groups of eight)
  std::uint32_t lowest = 0, highest = 0;  // see binRange
  std::uint32_t count[kBins] = {};
  std::uint32_t more[3][kBins] = {};  // tallies of positions 1, 2, 3 mod 4, merged into count

  // Counts the values per bin (no sign bit set, range from binRange). Four interleaved tallies:
  // neighbours often share a bin, and one array would chain each increment to the store before.
  void countBins(const float* x, std::size_t n)
  {
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
    {
      ++count[floatBits(x[i]) >> kBinShift];
      ++more[0][floatBits(x[i + 1]) >> kBinShift];
      ++more[1][floatBits(x[i + 2]) >> kBinShift];
      ++more[2][floatBits(x[i + 3]) >> kBinShift];
    }
    for (; i < n; ++i) ++count[floatBits(x[i]) >> kBinShift];
    forTouched([this](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t j = b; j < e; ++j)  // (ranges may overlap in bin 0: merging twice adds zeros)
      {
        count[j] += more[0][j] + more[1][j] + more[2][j];
        more[0][j] = more[1][j] = more[2][j] = 0;
      }
    });
  }
  // Zeroes this ring's counts again.
  void release()
  {
    forTouched([this](std::uint32_t b, std::uint32_t e) { std::fill(count + b, count + e, 0u); });
  }
  template <class F>
  void forTouched(F f) const
  {
    f(0, 1);
    if (lowest <= highest) f(lowest, highest + 1);
    f(kFiniteBins, kBins);
  }

  // The bin of rank k, searched upwards from bin `from` with `below` values under it; on return
  // `below` counts the values under the bin found.
  std::uint32_t find(std::size_t k, std::uint32_t from, std::size_t& below) const
  {
    std::uint32_t b = from;
    for (; below + count[b] <= k; ++b) below += count[b];
    return b;
  }
  // The same from the start, where no value lies in the bins (0, lowest) (see binRange).
  std::uint32_t findFirst(std::size_t k, std::size_t& below) const
  {
    std::uint32_t from = lowest;
    below = from > 0 ? count[0] : 0;  // only zeros in bin 0 then
    if (below > k) below = from = 0;  // one of them
    return find(k, from, below);
  }
};

/// Q25 and Q75 of the finite values of x[0, n) into lo, hi; false (nothing done) when a value
/// cannot be binned (sign bit set): the caller takes the general path.
bool binnedQuartiles(const float* x, std::size_t n, BinnedRing& r, float& lo, float& hi);
/// out = max(out, median + k * 1.4826 * MAD) of the finite values of x[0, n) (out unchanged
/// when none); false (nothing done) when a value cannot be binned.
bool binnedMedianPlusKMad(const float* x, std::size_t n, float k, BinnedRing& r, float& out);

/// Copies the values of x[0, n) (no sign bit set) in bin b0 or b1 to out (room for n + 8), in
/// order; returns how many.
std::size_t binCandidates(const float* x, std::size_t n, std::uint32_t b0, std::uint32_t b1, float* out);
/// Copies the deviations |x - med| in [lo, hi] to out (room for n + 8), in order; returns how
/// many, and in `under` how many deviations are below lo (NaN: in neither).
std::size_t bandCandidates(const float* x, std::size_t n, float med, float lo, float hi, float* out,
                           std::size_t& under);

}  // namespace detail
}  // namespace ring_curvature
