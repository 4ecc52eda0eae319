// Per-ring thresholds by exact O(K) selection (never a sort): the quantiles of Algorithm 1 and the robust median + k MAD.
#include "ring_curvature/classifier.hpp"
#include "compress_table.hpp"
#include "simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr float kDegToRad = 0.0174532925f;
constexpr float kMadToSigma = 1.4826f;  // MAD of a normal distribution is 0.6745 sigma
constexpr float kInf = std::numeric_limits<float>::infinity();

using detail::bitsFloat;
using detail::floatBits;
// Nearest rank of quantile q of n values: floor(q * (n - 1)).
inline std::size_t rankOf(std::size_t n, double q)
{
  return std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n - 1)));
}

using detail::orderedKey;

// Value of rank k in v[0, n) (reordered, never overwritten).
float selectRank(float* v, std::size_t n, std::size_t k)
{
  // Radix selection, most significant digit first: each pass counts the digit of the remaining
  // candidates and moves those in the bucket that holds rank k to the front. Same element as
  // nth_element, but without its unpredictable comparisons, which made this the second largest
  // cost of a frame (perf). The digits start at the highest bit in which the keys differ: the
  // values of one selection often share their sign, exponent and leading mantissa bits (the
  // azimuth spacings of a frame agree to ~1 %), and fixed digits from bit 31 down spent whole
  // passes over every value to learn nothing. The k-th key does not depend on the digits.
  // Swaps (or copies out to a local buffer), never overwrites: callers reuse all n values.
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
    // Digit width from the candidate count: a ring's few thousand values would otherwise spend
    // more time clearing, scanning and merging 2 x 2048 counters than counting themselves.
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
      // First narrowing of the caller's array: copy the candidates out to a local buffer
      // instead of swapping them to the front (a load, a store and no dependence on the
      // destination's old value per value, where a swap is two of each; ~1/5 of this function
      // under perf). The caller's values stay where they were, untouched.
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
}  // namespace

float selectQuantile(float* v, std::size_t n, double q)
{
  return n == 0 ? std::numeric_limits<float>::quiet_NaN() : selectRank(v, n, rankOf(n, q));
}

float selectNth(float* v, std::size_t n, std::size_t k) { return selectRank(v, n, k); }

namespace
{
// The general path, for rings the bins below cannot order (values with the sign bit set).
// Copies the finite values of v[b, e) to out (room for e - b); returns how many.
std::size_t gatherFinite(const std::vector<float>& v, std::uint32_t b, std::uint32_t e, float* out)
{
  std::size_t n = 0;
  for (std::uint32_t p = b; p < e; ++p)
    if (std::isfinite(v[p])) out[n++] = v[p];
  return n;
}

// median + k * 1.4826 * MAD of buf[0, n) (buf is reordered).
float medianPlusKMad(float* buf, std::size_t n, float k)
{
  const float med = selectQuantile(buf, n, 0.5);
  for (std::size_t i = 0; i < n; ++i) buf[i] = std::fabs(buf[i] - med);
  const float mad = selectQuantile(buf, n, 0.5);
  return med + k * kMadToSigma * mad;
}

// Ring features are non-negative (angles, variances, relative errors; NaN where undefined), and
// the bits of a non-negative float order like the float: bits >> 20 (exponent and three mantissa
// bits, eighths of a binade) bin a ring's values with no key transform and no copy. The ring is
// read in place; only the values of the bins that hold the wanted ranks (one to three percent)
// are copied out for the exact selection.
constexpr int kBinShift = 20;  // finer bins (19, 18) took more instructions (longer bound walks)
constexpr std::uint32_t kBins = 1u << (31 - kBinShift);          // every float with a clear sign bit
constexpr std::uint32_t kFiniteBins = 0x7F800000u >> kBinShift;  // the rest: +inf and NaN (exponent all ones)
inline float lowEdge(std::uint32_t bin) { return bitsFloat(bin << kBinShift); }
inline float highEdge(std::uint32_t bin) { return bitsFloat(((bin + 1) << kBinShift) - 1); }

// One ring's counts per bin. Between rings every counter is zero: a ring clears only the bins its
// values can fall in (+0's, [lowest, highest] and the non-finite ones; 170 to 230 bins on average
// on the test bags) where a memset of the whole histogram per ring and feature cost more.
struct BinnedRing
{
  float* cand;  // the wanted values (n + 8: the vector copy stores whole groups of eight)
  std::uint32_t lowest = 0, highest = 0;  // see binRange
  std::uint32_t count[kBins] = {};
  std::uint32_t more[3][kBins] = {};  // tallies of positions 1, 2, 3 mod 4, merged into count

  // Counts the values per bin (no sign bit set, range from binRange). Four interleaved tallies:
  // neighbours' values often share a bin, and with one array every increment waited for the
  // store of the one before.
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
    for (; b + 16 <= kBins; b += 16)  // 16 bins at a time first: most bins are empty
    {
      std::uint32_t s = 0;
      for (std::uint32_t j = 0; j < 16; ++j) s += count[b + j];
      if (below + s > k) break;
      below += s;
    }
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

// Whether x[0, n) can be binned (false when a value has its sign bit set: negative, -0 or a
// negative NaN, which the bins cannot order; the caller takes the general path then), and the
// bins its values fall in: `lowest`, the bin of the smallest value other than +0 (zeros are
// common, and a search up from bin 0 would cross every empty bin between them and the rest),
// and `highest`, that of the largest finite value. Also how many values are finite and how many
// lie below `cut` (a finite float >= 0), both counted on the bits (exact for floats with a
// clear sign bit; void when the answer is false).
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

// Eight lanes (GCC vector extension, element-wise: the same bits as scalar code; AVX2 in the
// AVX2 clones, with one lane permutation for the copy-out).
using V8f = float __attribute__((vector_size(32)));
using V8i = std::int32_t __attribute__((vector_size(32)));

// Stores the lanes of v whose `in` lanes are set (all ones) at out + m, in order, and advances m.
// Writes all eight lanes: those past the kept ones are overwritten by the next call or unused.
// Where the wanted values (a few percent, anywhere in the ring) were flagged first and blocks
// holding one copied, that branch mispredicted about half the time.
__attribute__((always_inline)) inline void appendLanes(const V8f& v, std::uint32_t mask, float* out, std::size_t& m)
{
  V8i lane;
  std::memcpy(&lane, kCompress.lane[mask], sizeof lane);
#if defined(__clang__)  // (the sanitizer and fuzz builds): no variable shuffle builtin, lane by lane
  V8f packed;
  for (int j = 0; j < 8; ++j) packed[j] = v[lane[j]];
#else
  const V8f packed = __builtin_shuffle(v, lane);
#endif
  std::memcpy(out + m, &packed, sizeof packed);
  m += static_cast<std::size_t>(__builtin_popcount(mask));
}
// The same for the wanted lanes of x[i, n) that group(j, v, in) gives for j = i, i + 8, ...,
// two groups a step (one sum across the lanes for both masks); returns where it stopped.
template <class Group>
__attribute__((always_inline)) inline std::size_t appendGroups(std::size_t i, std::size_t n, Group group, float* out,
                                                               std::size_t& m)
{
  const V8i bit = {1, 2, 4, 8, 16, 32, 64, 128};
  for (; i + 16 <= n; i += 16)
  {
    V8f a, b;
    V8i in_a, in_b;
    group(i, a, in_a);
    group(i + 8, b, in_b);
    V8i s = (in_a & bit) | (in_b & (bit << 8));  // the masks' bits, summed across the lanes
    s += __builtin_shufflevector(s, s, 4, 5, 6, 7, 0, 1, 2, 3);
    s += __builtin_shufflevector(s, s, 2, 3, 0, 1, 6, 7, 4, 5);
    s += __builtin_shufflevector(s, s, 1, 0, 3, 2, 5, 4, 7, 6);
    const auto mask = static_cast<std::uint32_t>(s[0]);
    appendLanes(a, mask & 0xFFu, out, m);
    appendLanes(b, mask >> 8, out, m);
  }
  for (; i + 8 <= n; i += 8)
  {
    V8f a;
    V8i in_a;
    group(i, a, in_a);
    V8i s = in_a & bit;
    s += __builtin_shufflevector(s, s, 4, 5, 6, 7, 0, 1, 2, 3);
    s += __builtin_shufflevector(s, s, 2, 3, 0, 1, 6, 7, 4, 5);
    s += __builtin_shufflevector(s, s, 1, 0, 3, 2, 5, 4, 7, 6);
    appendLanes(a, static_cast<std::uint32_t>(s[0]), out, m);
  }
  return i;
}

// Copies the values of x[0, n) (no sign bit set) in bin b0 or b1 to out (room for n + 8), in
// order; returns how many.
RC_SIMD_CLONES std::size_t binCandidates(const float* x, std::size_t n, std::uint32_t b0, std::uint32_t b1, float* out)
{
  const auto c0 = static_cast<std::int32_t>(b0), c1 = static_cast<std::int32_t>(b1);
  const V8i v0 = {c0, c0, c0, c0, c0, c0, c0, c0}, v1 = {c1, c1, c1, c1, c1, c1, c1, c1};
  std::size_t m = 0;
  auto group = [&](std::size_t j, V8f& v, V8i& in) __attribute__((always_inline)) {
    V8i u;
    std::memcpy(&v, x + j, sizeof v);
    std::memcpy(&u, x + j, sizeof u);
    const V8i bin = u >> kBinShift;
    in = (bin == v0) | (bin == v1);
  };
  for (std::size_t i = appendGroups(0, n, group, out, m); i < n; ++i)
  {
    const std::uint32_t bin = floatBits(x[i]) >> kBinShift;
    out[m] = x[i];  // overwritten by the next one unless this one is wanted
    m += ((bin == b0) | (bin == b1)) ? 1 : 0;
  }
  return m;
}

// Copies the deviations |x - med| in [lo, hi] to out (room for n + 8), in order; returns how
// many, and in `under` how many deviations are below lo (NaN: in neither).
RC_SIMD_CLONES std::size_t bandCandidates(const float* x, std::size_t n, float med, float lo, float hi, float* out,
                                          std::size_t& under)
{
  const V8f vmed = {med, med, med, med, med, med, med, med};
  const V8f vlo = {lo, lo, lo, lo, lo, lo, lo, lo}, vhi = {hi, hi, hi, hi, hi, hi, hi, hi};
  const V8i abs_mask = {0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF,
                        0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF, 0x7FFFFFFF};
  V8i below = {};  // minus the count per lane
  std::size_t m = 0;
  auto group = [&](std::size_t j, V8f& d, V8i& in) __attribute__((always_inline)) {
    V8f v;
    std::memcpy(&v, x + j, sizeof v);
    const V8f diff = v - vmed;
    V8i bits;
    std::memcpy(&bits, &diff, sizeof bits);
    bits &= abs_mask;  // fabs
    std::memcpy(&d, &bits, sizeof d);
    below += d < vlo;
    in = (d >= vlo) & (d <= vhi);
  };
  std::size_t i = appendGroups(0, n, group, out, m);
  std::uint32_t count = 0;
  for (int l = 0; l < 8; ++l) count -= static_cast<std::uint32_t>(below[l]);
  for (; i < n; ++i)
  {
    const float d = std::fabs(x[i] - med);
    count += d < lo ? 1u : 0u;
    out[m] = d;  // overwritten by the next one unless this one is wanted
    m += ((d >= lo) & (d <= hi)) ? 1 : 0;
  }
  under = count;
  return m;
}

// The deviations |v - med| of the values of a bin lie between bounds set by the bin's edges
// (float subtraction is monotonic), growing with the distance from med's bin on either side.
// Taking med's bin, then the others in increasing order of their lower (upper) bound until more
// than `rank` values are taken, the last bound taken is a lower (with med's bin's own, an upper)
// bound of the rank-th deviation, the MAD.
// Bins are taken one at a time, empty ones too (they add nothing, so the bins with values are
// taken in the same order and the walk ends at the same one): a step without a branch, where
// skipping the empty ones mispredicted at every gap. Only the stretches where no value can be,
// (0, lowest) and (highest, +inf), are jumped. The two walks (lower and upper bound) step
// together: two independent chains of dependent steps.
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

// An upper bound of the MAD whatever the median in bin med_bin: a value of bin j deviates from
// any median of med_bin by at most the distance between their farthest edges (float subtraction
// is monotonic), and the bins taken outwards in increasing order of that bound until more than
// `rank` values are taken leave the rank-th deviation at or below the last bound taken. The same
// walk as deviationBounds, from the histogram alone: no exact median needed.
// Whether median + scale * MAD < out is certain from the histogram alone: top + scale * (the
// ceiling) < out, with top the upper edge of med_bin. The bounds taken only grow along the walk
// (it takes the smaller of two growing sequences), and float + and * by scale >= 0 are monotonic,
// so the walk stops, false, at the first bound that already reaches out.
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

// Value of rank k in c[0, m) (m > k), the wanted bins' values. Few: counted for each value, those
// below it and those not above it (branch-free and vectorized, where nth_element's comparisons
// mispredict half the time; twice as fast up to ~50). Without -0 or NaN, equal means same bits.
float selectCandidate(float* c, std::size_t m, std::size_t k)
{
  if (m > 48) return selectRank(c, m, k);
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

// Q25 and Q75 of the finite values of x[0, n); false when they need the general path.
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

// max(out, median + k * 1.4826 * MAD) of the finite values of x[0, n) (out unchanged when none
// is finite); false when they need the general path.
RC_SIMD_CLONES bool binnedMedianPlusKMad(const float* x, std::size_t n, float k, BinnedRing& r, float& out)
{
  // The floor `out` usually wins (a ring's typical roughness or jump lies far below what noise
  // alone can produce): when upper bounds of the median and the MAD give less than `out`, so
  // does the exact value (float + and * by a scale >= 0 are monotonic), and the work for it is
  // skipped. `<`: max(v, out) is then out. First from two counts: if more than `rank` values lie
  // below `cut`, the median does, and so do the deviations of those values from it (both in
  // [0, cut)), so the MAD is at most cut: no histogram at all.
  const float scale = k * kMadToSigma;
  std::size_t finite, under;
  if (!binRange(x, n, floorCut(out, scale), r.lowest, r.highest, finite, under)) return false;
  if (finite == 0) return true;  // nothing counted yet: no histogram to release
  const std::size_t rank = rankOf(finite, 0.5);
  if (under > rank) return true;
  r.countBins(x, n);
  std::size_t below = 0;
  const std::uint32_t b = r.findFirst(rank, below);
  // Then from the histogram: the median's bin and the MAD's ceiling (ceilingBelow); when
  // they suffice, the two passes over the ring and the two selections are skipped.
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
}  // namespace

void Classifier::computeThresholds(const ScanGrid& grid, const Features& f, const Params& P,
                                   std::vector<RingThresholds>& out)
{
  out.assign(static_cast<std::size_t>(grid.num_rings), RingThresholds{});
  const bool quartile = P.classifier_mode == ClassifierMode::Quartile;
  const float sigma = P.range_noise;
  std::uint32_t largest = 0;
  for (int n = 0; n < grid.num_rings; ++n) largest = std::max(largest, grid.ringSize(n));
  scratch_.resize(largest + 8u);  // grown once: no allocation in later frames
  BinnedRing r;  // all counters zero
  r.cand = scratch_.data();
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    RingThresholds& t = out[static_cast<std::size_t>(n)];
    if (quartile)
    {
      // Algorithm 1: Q25 and Q75 of each feature over the ring, each by one O(K) selection.
      auto quartiles = [&](const std::vector<float>& v, float& lo, float& hi) {
        if (binnedQuartiles(v.data() + b, e - b, r, lo, hi)) return;
        const std::size_t k = gatherFinite(v, b, e, r.cand);
        lo = selectQuantile(r.cand, k, 0.25);
        hi = selectQuantile(r.cand, k, 0.75);
        if (k == 0) lo = hi = kInf;  // nothing finite: no point passes a "greater than" test
      };
      float s_lo;
      quartiles(f.curvature, t.curvature_low, t.curvature_high);
      quartiles(f.smoothness, s_lo, t.smoothness_high);
      quartiles(f.discontinuity, t.discontinuity_low, t.discontinuity_high);
      continue;
    }
    // Robust: median + k * MAD on the ring, never below what noise alone can produce.
    auto robust = [&](const std::vector<float>& v, float floor) {
      float thr = floor;
      if (binnedMedianPlusKMad(v.data() + b, e - b, P.robust_k, r, thr)) return thr;
      const std::size_t k = gatherFinite(v, b, e, r.cand);
      return k ? std::max(medianPlusKMad(r.cand, k, P.robust_k), floor) : floor;
    };
    t.curvature_high = robust(f.turning, P.edge_min_angle_deg * kDegToRad);
    t.curvature_low = t.curvature_high;
    t.smoothness_high = robust(f.smoothness, (P.noise_floor_k * sigma) * (P.noise_floor_k * sigma));
    t.discontinuity_high = robust(f.discontinuity, P.discontinuity_mode == DiscontinuityMode::Jump ? P.jump_min_ratio : 0.9f);
    t.discontinuity_low = t.discontinuity_high;
  }
}

}  // namespace ring_curvature
