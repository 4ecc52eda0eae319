// The grid's measured azimuth resolution: the median spacing of neighbouring samples on a ring,
// found in one pass over the spacings with a bracket from a sample.
#include "ring_curvature/scan_grid.hpp"

#include "grow.hpp"
#include "simd_clones.hpp"

#include "ring_curvature/classifier.hpp"  // selectNth

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr float kTwoPi = 6.28318530717959f;
constexpr float kDeg = kPi / 180.0f;

float wrapPi(float a)
{
  if (a >= kPi) a -= kTwoPi;
  if (a < -kPi) a += kTwoPi;
  return a;
}

// The spacings |wrapPi(az[p] - az[p - 1])| of a ring (b, e) to out[0, e - b - 1); organized
// clouds per column between the two samples.
RC_SIMD_CLONES void azimuthSpacings(std::size_t b, std::size_t e, const float* __restrict az, float* __restrict out)
{
  for (std::size_t p = b + 1; p < e; ++p) out[p - b - 1] = std::fabs(wrapPi(az[p] - az[p - 1]));
}
RC_SIMD_CLONES void columnSpacings(std::size_t b, std::size_t e, const float* __restrict az,
                                   const std::uint32_t* __restrict column, float* __restrict out)
{
  for (std::size_t p = b + 1; p < e; ++p)
    out[p - b - 1] = std::fabs(wrapPi(az[p] - az[p - 1])) / static_cast<float>(column[p] - column[p - 1]);
}

// Whether a spacing counts: same-firing duplicates (near 0) and gaps (> 5 deg) do not.
inline bool kept(float d) { return (d > 1e-5f) & (d < 5.0f * kDeg); }
}  // namespace

void ScanGridBuilder::measureResolution(const Params& params, ScanGrid& grid)
{
  if (params.azimuth_resolution_deg > 0.0f)
  {
    grid.azimuth_resolution = params.azimuth_resolution_deg * kDeg;
    return;
  }
  // Median spacing of neighbouring samples on the same ring (the kept ones, see kept()): the
  // element of rank n / 2 of the n kept, as nth_element would give. For organized clouds the
  // spacing per column. First every ring's spacings, in loops that vectorize.
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
      columnSpacings(b, e, az, column_.data(), d + total);
    else
      azimuthSpacings(b, e, az, d + total);
    total += e - b - 1;
  }
  float median;
  if (!bracketedMedian(d, total, median))
  {
    // A small frame (or a missed bracket): the kept spacings compacted without branches, then
    // the radix selection over all of them.
    std::size_t n = 0;
    for (std::size_t i = 0; i < total; ++i)
    {
      const float v = d[i];
      d[n] = v;
      n += kept(v) ? 1 : 0;
    }
    median = n > 0 ? selectNth(d, n, n / 2) : kTwoPi / static_cast<float>(largest);  // none kept
  }
  grid.azimuth_resolution = median;
}

bool ScanGridBuilder::bracketedMedian(const float* d, std::size_t total, float& median)
{
  // Most spacings are about the same value, and the radix selection moves nearly all of them at
  // every digit. So a bracket [lo, hi] around the median from an even sample of the kept
  // spacings, then one pass over all spacings that counts the kept ones, those below lo, and
  // copies out those inside; the selection runs on those few. The result is the element of rank
  // n / 2 all the same; if the bracket misses that rank (it holds it with overwhelming odds),
  // this returns false and the caller selects among all. (A pass of its own compacted the kept
  // spacings first; the bracket pass now does without it.)
  constexpr std::size_t kSample = 1024, kSpread = 64;  // ~4 sigma of the sample's median rank
  if (total < 8 * kSample) return false;
  float sample[kSample];
  std::size_t ns = 0;
  const std::size_t stride = total / kSample;
  for (std::size_t j = 0; j < kSample; ++j)
  {
    const float v = d[j * stride];
    sample[ns] = v;
    ns += kept(v) ? 1 : 0;
  }
  if (ns < kSample / 2) return false;
  const std::size_t spread = kSpread * ns / kSample;
  // (the radix selection here too: nth_element's comparisons mispredicted ~1500 times a frame)
  const float lo = selectNth(sample, ns, ns / 2 - spread);
  const float hi = selectNth(sample, ns, ns / 2 + spread);
  growTo(inside_, total + 1);
  float* const in = inside_.data();
  // Kept spacings are positive, so their bits order like them: one unsigned comparison tells
  // inside from outside.
  const std::uint32_t lo_bits = detail::floatBits(lo), span = detail::floatBits(hi) - lo_bits;
  std::size_t n = 0, below = 0, m = 0;
  for (std::size_t i = 0; i < total; ++i)
  {
    const float v = d[i];
    const std::uint32_t u = detail::floatBits(v);
    const std::size_t k = kept(v) ? 1 : 0;
    n += k;
    below += k & (u < lo_bits ? 1u : 0u);
    in[m] = v;  // overwritten by the next one unless this one is kept and inside
    m += k & (u - lo_bits <= span ? 1u : 0u);
  }
  const std::size_t rank = n / 2;
  if (!(below <= rank && rank < below + m)) return false;
  median = selectNth(in, m, rank - below);
  return true;
}

}  // namespace ring_curvature
