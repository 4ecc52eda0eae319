// Histogram selection of a ring's thresholds (see binned_selection.hpp).
#include "classification/binned_selection.hpp"
#include "common/float_bits.hpp"

#include "classification/rank_select.hpp"
#include "common/simd_clones.hpp"

#include <cmath>
#include <limits>

namespace ring_curvature
{
namespace detail
{
namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();

// Whether x[0, n) can be binned (no sign bit set: the bins cannot order -0, negatives or -NaN); its
// `lowest` bin but +0's (so searches skip the empty bins after the zeros), `highest` finite bin, and
// counts of finite values and of those below `cut` (>= 0), on the bits (exact for a clear sign bit).
RC_SIMD_CLONES bool binRange(const float* x, std::size_t n, float cut, std::uint32_t& lowest, std::uint32_t& highest,
                             std::size_t& finite, std::size_t& under)
{
  const std::uint32_t cut_bits = floatBits(cut);
  std::uint32_t sign = 0, low = 0xFFFFFFFFu, high = 0, fin = 0, below = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t u = floatBits(x[i]);
    sign |= u;
    low = std::min(low, u - 1);  // +0 wraps to the top
    high = std::max(high, u & detail::maskOf(u < 0x7F800000u));  // finite only (a mask: vectorizes)
    fin += u < 0x7F800000u ? 1u : 0u;
    below += u < cut_bits ? 1u : 0u;
  }
  lowest = (low + 1) >> kBinShift;
  highest = high >> kBinShift;
  finite = fin;
  under = below;
  return (sign >> 31) == 0;
}

// The largest cut (roughly) such that a median and a MAD both at most `cut` give
// median + scale * MAD < out, evaluated as binnedMedianPlusKMad does (0 when none is found: no
// value lies below it).
float floorCut(float out, float scale)
{
  if (!(scale >= 0.0f) || !(out > 0.0f) || !std::isfinite(out)) return 0.0f;
  float cut = out / (1.0f + scale);
  for (int i = 0; i < 4; ++i, cut *= 0.999f)
    if (cut + scale * cut < out) return cut;
  return 0.0f;
}

// A bin's deviations |v - med| lie between bounds set by its edges (float subtraction is monotonic):
// taking bins by increasing lower (upper) bound until more than `rank` values are taken, the last
// bound bounds the MAD. Empty bins are taken too (no branch), only (0, lowest) and (highest, +inf)
// jumped; the lower and upper walks step together (two independent dependency chains).
struct DeviationWalk
{
  std::uint32_t up, dn;  // next bin above; one past the next below
  std::size_t seen;
  float d;
};
// (Distances upwards from `from_up` and downwards from `from_dn`: both med here, the edges of
// med's bin in ceilingBelow.)
template <bool kUpper>
inline void deviationStep(const BinnedRing& r, std::uint32_t lowest, float from_up, float from_dn, DeviationWalk& w)
{
  const float d_up = w.up < kFiniteBins ? (kUpper ? highEdge(w.up) : lowEdge(w.up)) - from_up : kInf;
  const float d_dn = w.dn > 0 ? from_dn - (kUpper ? lowEdge(w.dn - 1) : highEdge(w.dn - 1)) : kInf;
  const bool take_up = d_up <= d_dn;
  w.d = take_up ? d_up : d_dn;
  w.seen += r.count[take_up ? w.up : w.dn - 1];
  w.up += take_up ? 1 : 0;
  w.up = w.up > r.highest ? kFiniteBins : w.up;
  w.dn -= take_up ? 0 : 1;
  w.dn = w.dn == lowest ? 1 : w.dn;  // below `lowest`, only bin 0 may hold values
}
// Lower and upper bounds of the MAD, around med in bin med_bin.
void deviationBounds(const BinnedRing& r, std::uint32_t med_bin, float med, std::size_t rank, float& lo, float& hi)
{
  const float own = std::max(highEdge(med_bin) - med, med - lowEdge(med_bin));
  const std::uint32_t lowest = r.lowest > 1 ? r.lowest : kBins;  // (kBins: no jump)
  DeviationWalk a{med_bin + 1 > r.highest ? kFiniteBins : med_bin + 1, med_bin == lowest ? 1 : med_bin,
                  r.count[med_bin], 0.0f};
  DeviationWalk b = a;
  b.d = own;
  while (a.seen <= rank && b.seen <= rank)
  {
    deviationStep<false>(r, lowest, med, med, a);
    deviationStep<true>(r, lowest, med, med, b);
  }
  while (a.seen <= rank) deviationStep<false>(r, lowest, med, med, a);
  while (b.seen <= rank) deviationStep<true>(r, lowest, med, med, b);
  lo = a.d;  // 0 where med's own bin holds the rank
  hi = std::max(b.d, own);
}

// Whether median + scale * MAD < out is certain from the histogram alone: the walk on the farthest
// edges' distances bounds the MAD for any median in med_bin, and top + scale * bound (top: its upper
// edge) only grows along it (monotonic float + and *): false at the first bound reaching out.
bool ceilingBelow(const BinnedRing& r, std::uint32_t med_bin, std::size_t rank, float scale, float out)
{
  const float top = highEdge(med_bin), bottom = lowEdge(med_bin);
  const std::uint32_t lowest = r.lowest > 1 ? r.lowest : kBins;  // (kBins: no jump)
  DeviationWalk w{med_bin + 1 > r.highest ? kFiniteBins : med_bin + 1, med_bin == lowest ? 1 : med_bin,
                  r.count[med_bin], top - bottom};
  while (w.seen <= rank)
  {
    if (!(top + scale * w.d < out)) return false;
    deviationStep<true>(r, lowest, bottom, top, w);
  }
  return top + scale * w.d < out;
}

// Value of rank k in c[0, m) (m > k): few, so per value those below and not above it are counted,
// branch-free (nth_element's comparisons mispredict). Without -0 or NaN, equal means same bits.
float selectCandidate(float* c, std::size_t m, std::size_t k)
{
  if (m > 48) return selectNth(c, m, k);
  for (std::size_t i = 0;; ++i)
  {
    const float v = c[i];
    std::uint32_t below = 0, not_above = 0;
    for (std::size_t j = 0; j < m; ++j)
    {
      below += c[j] < v ? 1u : 0u;
      not_above += c[j] <= v ? 1u : 0u;
    }
    if (below <= k && k < not_above) return v;
  }
}

}  // namespace

RC_SIMD_CLONES bool binnedQuartiles(const float* x, std::size_t n, BinnedRing& r, float& lo, float& hi)
{
  std::size_t finite, under;
  if (!binRange(x, n, 0.0f, r.lowest, r.highest, finite, under)) return false;
  if (finite == 0)
  {
    lo = hi = kInf;  // nothing finite: no point passes a "greater than" test
    return true;
  }
  r.countBins(x, n);
  const std::size_t k_lo = rankOf(finite, 0.25), k_hi = rankOf(finite, 0.75);
  std::size_t below_lo = 0;
  const std::uint32_t b_lo = r.findFirst(k_lo, below_lo);
  std::size_t below_hi = below_lo;
  const std::uint32_t b_hi = r.find(k_hi, b_lo, below_hi);
  const std::size_t m = binCandidates(x, n, b_lo, b_hi, r.cand);
  // the candidates of the lower bin come first in the order of the values
  const std::size_t r_hi = k_hi - below_hi + (b_hi != b_lo ? r.count[b_lo] : 0);
  r.release();
  lo = selectCandidate(r.cand, m, k_lo - below_lo);
  hi = selectCandidate(r.cand, m, r_hi);
  return true;
}

RC_SIMD_CLONES bool binnedMedianPlusKMad(const float* x, std::size_t n, float k, BinnedRing& r, float& out)
{
  // The floor `out` usually wins (roughness lies far below noise): if upper bounds of median and MAD
  // give less, so does the exact value. First from counts: over `rank` values below `cut` bound both.
  const float scale = k * kMadToSigma;
  std::size_t finite, under;
  if (!binRange(x, n, floorCut(out, scale), r.lowest, r.highest, finite, under)) return false;
  if (finite == 0) return true;  // nothing counted yet: no histogram to release
  const std::size_t rank = rankOf(finite, 0.5);
  if (under > rank) return true;
  r.countBins(x, n);
  std::size_t below = 0;
  const std::uint32_t b = r.findFirst(rank, below);
  // Then from the histogram: the median's bin and the MAD's ceiling may suffice (ceilingBelow).
  if (scale >= 0.0f && ceilingBelow(r, b, rank, scale, out))
  {
    r.release();
    return true;
  }
  std::size_t m = binCandidates(x, n, b, b, r.cand);
  const float med = selectCandidate(r.cand, m, rank - below);
  float lo, hi;
  deviationBounds(r, b, med, rank, lo, hi);
  r.release();
  m = bandCandidates(x, n, med, lo, hi, r.cand, below);
  const float mad = selectCandidate(r.cand, m, rank - below);
  out = std::max(med + scale * mad, out);  // (k * kMadToSigma * mad: the same product)
  return true;
}

}  // namespace detail
}  // namespace ring_curvature
