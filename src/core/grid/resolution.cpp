// The grid's measured azimuth resolution: the median spacing of neighbouring samples on a ring,
// found in one pass over the spacings with a bracket from a sample.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

#include "common/angles.hpp"
#include "common/float_bits.hpp"
#include "common/grow.hpp"
#include "common/simd_clones.hpp"

#include "classification/rank_select.hpp"  // selectNth

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

namespace
{
constexpr float kDeg = kPi / 180.0f;

// The spacings |wrapPi(az[p] - az[p - 1])| of a ring (b, e) to out[0, e - b - 1); organized
// clouds per column between the two samples (columnSpacings).
RC_SIMD_CLONES void azimuthSpacings(std::size_t b, std::size_t e, const float* __restrict az, float* __restrict out)
{
  for (std::size_t p = b + 1; p < e; ++p) out[p - b - 1] = std::fabs(wrapPi(az[p] - az[p - 1]));
}
// `index`: the input indices; in a row of an organized cloud two samples' columns differ by as
// much as their indices.
RC_SIMD_CLONES void columnSpacings(std::size_t b, std::size_t e, const float* __restrict az,
                                   const std::uint32_t* __restrict index, float* __restrict out)
{
  for (std::size_t p = b + 1; p < e; ++p)
    out[p - b - 1] = std::fabs(wrapPi(az[p] - az[p - 1])) / static_cast<float>(index[p] - index[p - 1]);
}

// Whether a spacing counts: same-firing duplicates (near 0) and gaps (> 5 deg) do not.
inline bool kept(float d) { return (d > 1e-5f) & (d < 5.0f * kDeg); }
// The same test on the bits read as a signed integer, for every float: non-negative floats
// order like their bits, and negative ones (-0 and -NaN included) read as negative integers,
// +inf and +NaN as integers above those of 5 deg. kept(d) iff keptAbove() < bitsOf(d) < keptUnder().
inline std::int32_t bitsOf(float v) { return static_cast<std::int32_t>(detail::floatBits(v)); }
inline std::int32_t keptAbove() { return bitsOf(1e-5f); }
inline std::int32_t keptUnder() { return bitsOf(5.0f * kDeg); }

// The bracket pass's counts: kept spacings, those of them below the bracket, and those inside.
struct BracketCounts
{
  std::size_t n = 0, below = 0, m = 0;
};

// The bracket pass over d[0, total) for a bracket [lo, hi] of kept bits (so whatever is inside
// is kept): the counts, and those inside appended to in (writing one slot past them).
RC_SIMD_CLONES BracketCounts bracketPass(const float* d, std::size_t total, std::int32_t lo, std::int32_t hi, float* in)
{
  const std::int32_t above = keptAbove(), under = keptUnder();
  std::size_t n = 0, below = 0, m = 0;
  for (std::size_t i = 0; i < total; ++i)
  {
    const std::int32_t u = bitsOf(d[i]);
    n += (u > above) & (u < under);
    below += (u > above) & (u < lo);
    in[m] = d[i];  // overwritten by the next one unless this one is inside
    m += (u >= lo) & (u <= hi);
  }
  return {n, below, m};
}
}  // namespace

void ScanGridBuilder::measureResolution(const Params& params, ScanGrid& grid)
{
  if (params.azimuth_resolution_deg > 0.0f)
  {
    grid.azimuth_resolution = params.azimuth_resolution_deg * kDeg;
    return;
  }
  // Median kept spacing of ring neighbours (per column when organized): rank n / 2 of the n kept,
  // as nth_element gives. First every ring's spacings, in loops that vectorize.
  tmp_f_.resize(sorted_az_.size() + 1);
  float* const d = tmp_f_.data();
  const float* const az = sorted_az_.data();
  std::size_t total = 0;
  // (the rings as they came: identical returns folded by sortRings count here too)
  std::uint32_t largest = std::max(1u, grid.organized ? 0u : unfolded_largest_);
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    largest = std::max(largest, e - b);
    if (e - b < 2) continue;
    if (grid.organized)
      columnSpacings(b, e, az, tmp_index_.data(), d + total);
    else
      azimuthSpacings(b, e, az, d + total);
    total += e - b - 1;
  }
  grid.azimuth_resolution = spacing_median_(d, total, kTwoPi / static_cast<float>(largest));  // none kept
}

float SpacingMedian::operator()(float* d, std::size_t total, float none)
{
  float median;
  bracketed_ = fromBracket(d, total, median);
  if (bracketed_) return median;
  // A small frame (or a missed bracket): the kept spacings compacted without branches, then
  // the radix selection over all of them.
  std::size_t n = 0;
  for (std::size_t i = 0; i < total; ++i)
  {
    const float v = d[i];
    d[n] = v;
    n += kept(v) ? 1 : 0;
  }
  return n > 0 ? selectNth(d, n, n / 2) : none;
}

bool SpacingMedian::fromBracket(const float* d, std::size_t total, float& median)
{
  // Most spacings are about equal, so a selection over all would move nearly all at every digit:
  // a bracket from an even sample, one pass counting and copying out those inside, selection among
  // those (rank n / 2 exactly, or false if missed). Positive floats' bits order like them.
  constexpr std::size_t kSample = 1024, kSpread = 64;  // ~4 sigma of the sample's median rank
  if (total < 8 * kSample) return false;
  float sample[kSample];
  std::size_t ns = 0;
  const std::size_t stride = total / kSample;
  for (std::size_t j = 0; j < kSample; ++j)
  {
    sample[ns] = d[j * stride];
    ns += kept(sample[ns]) ? 1 : 0;
  }
  if (ns < kSample / 2) return false;
  const std::size_t spread = kSpread * ns / kSample;
  const float lo = selectNth(sample, ns, ns / 2 - spread), hi = selectNth(sample, ns, ns / 2 + spread);
  growTo(inside_, total + 1);  // (bracketPass writes one slot past the inside ones)
  const BracketCounts c = bracketPass(d, total, bitsOf(lo), bitsOf(hi), inside_.data());
  const std::size_t rank = c.n / 2;
  if (!(c.below <= rank && rank < c.below + c.m)) return false;
  median = lo == hi ? lo : selectNth(inside_.data(), c.m, rank - c.below);  // (equal spacings: often)
  return true;
}

}  // namespace ring_curvature
