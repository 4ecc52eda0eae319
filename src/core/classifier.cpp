// Per-ring thresholds by exact O(K) selection (never a sort) and the labelling rules.
#include "ring_curvature/classifier.hpp"
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
// bits, eighths of a binade) bin a ring's values with no key transform, no min/max pass and no
// copy. The ring is read in place; only the values of the bins that hold the wanted ranks (one
// to three percent) are copied out for the exact selection.
constexpr int kBinShift = 20;
constexpr std::uint32_t kBins = 2048;        // every float with a clear sign bit
constexpr std::uint32_t kFiniteBins = 2040;  // bins 2040..2047: +inf and NaN (exponent all ones)
inline float lowEdge(std::uint32_t bin) { return bitsFloat(bin << kBinShift); }
inline float highEdge(std::uint32_t bin) { return bitsFloat(((bin + 1) << kBinShift) - 1); }

// One ring's values by bin, and the copy-out of the values of wanted bins.
struct BinnedRing
{
  std::uint16_t* bin;  // bin of each value (n)
  std::uint8_t* flag;  // 1 where a value is wanted (n)
  float* cand;         // the wanted values (n + 1)
  std::uint32_t count[kBins];

  // Counts the values per bin; returns how many are finite.
  std::size_t countBins(std::size_t n)
  {
    std::memset(count, 0, sizeof count);
    for (std::size_t i = 0; i < n; ++i) ++count[bin[i]];
    for (std::uint32_t b = kFiniteBins; b < kBins; ++b) n -= count[b];
    return n;
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
  // The same from the start, where no value lies in the bins (0, lowest) (see binValues).
  std::uint32_t findFirst(std::size_t k, std::uint32_t lowest, std::size_t& below) const
  {
    below = lowest > 0 ? count[0] : 0;  // only zeros in bin 0 then
    if (below > k) below = lowest = 0;  // one of them
    return find(k, lowest, below);
  }

  // Copies value(i) of every i in bin b0 or b1 to cand; returns how many.
  template <class Value>
  std::size_t gather(std::size_t n, std::uint32_t bin0, std::uint32_t bin1, Value value)
  {
    const auto b0 = static_cast<std::uint16_t>(bin0), b1 = static_cast<std::uint16_t>(bin1);
    // flags first (vectorized; 16-bit bins compare 8 at a time); local pointers, as a byte
    // store may alias the members
    const std::uint16_t* const bn = bin;
    std::uint8_t* const fl = flag;
    for (std::size_t i = 0; i < n; ++i) fl[i] = static_cast<std::uint8_t>((bn[i] == b0) | (bn[i] == b1));
    return copyFlagged(n, value);
  }
  // Copies value(i) of every flagged i to cand, only in the rare blocks of 8 holding one.
  template <class Value>
  std::size_t copyFlagged(std::size_t n, Value value)
  {
    const std::uint8_t* const fl = flag;
    float* const out = cand;
    std::size_t m = 0, i = 0;
    auto copy = [&](std::size_t j) {
      out[m] = value(j);  // overwritten by the next one unless this one is wanted
      m += fl[j];
    };
    for (; i + 8 <= n; i += 8)
    {
      std::uint64_t any;
      std::memcpy(&any, fl + i, sizeof any);
      if (any == 0) continue;
      for (std::size_t j = i; j < i + 8; ++j) copy(j);
    }
    for (; i < n; ++i) copy(i);
    return m;
  }
};

// Bins of x[0, n); false when a value has its sign bit set (negative, -0 or a negative NaN),
// which the bins cannot order: the caller takes the general path then. `lowest` is the bin of
// the smallest value other than +0 (zeros are common, and a search up from bin 0 would cross
// every empty bin between them and the rest).
RC_SIMD_CLONES bool binValues(const float* x, std::size_t n, std::uint16_t* bin, std::uint32_t& lowest)
{
  std::uint32_t sign = 0, low = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t u = floatBits(x[i]);
    sign |= u;
    low = std::min(low, u - 1);  // +0 wraps to the top
    bin[i] = static_cast<std::uint16_t>(u >> kBinShift);
  }
  lowest = (low + 1) >> kBinShift;
  return (sign >> 31) == 0;
}

// The deviations |v - med| of the values of a bin lie between bounds set by the bin's edges
// (float subtraction is monotonic), growing with the distance from med's bin on either side.
// Taking med's bin, then the others in increasing order of their lower (upper) bound until more
// than `rank` values are taken, the last bound taken is a lower (with med's bin's own, an upper)
// bound of the rank-th deviation, the MAD.
RC_SIMD_CLONES float deviationBound(const BinnedRing& r, std::uint32_t med_bin, float med, std::size_t rank, bool upper)
{
  const float own = upper ? std::max(highEdge(med_bin) - med, med - lowEdge(med_bin)) : 0.0f;
  float d = own;
  std::size_t seen = r.count[med_bin];
  std::uint32_t up = med_bin + 1, dn = med_bin;  // next bin above; one past the next below
  while (seen <= rank)
  {
    while (up < kFiniteBins && r.count[up] == 0) ++up;
    while (dn > 0 && r.count[dn - 1] == 0) --dn;
    const float d_up = up < kFiniteBins ? (upper ? highEdge(up) : lowEdge(up)) - med : kInf;
    const float d_dn = dn > 0 ? med - (upper ? lowEdge(dn - 1) : highEdge(dn - 1)) : kInf;
    if (d_up <= d_dn)
    {
      d = d_up;
      seen += r.count[up++];
    }
    else
    {
      d = d_dn;
      seen += r.count[--dn];
    }
  }
  return std::max(d, own);
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
  std::uint32_t lowest;
  if (!binValues(x, n, r.bin, lowest)) return false;
  const std::size_t finite = r.countBins(n);
  if (finite == 0)
  {
    lo = hi = kInf;  // nothing finite: no point passes a "greater than" test
    return true;
  }
  const std::size_t k_lo = rankOf(finite, 0.25), k_hi = rankOf(finite, 0.75);
  std::size_t below_lo = 0;
  const std::uint32_t b_lo = r.findFirst(k_lo, lowest, below_lo);
  std::size_t below_hi = below_lo;
  const std::uint32_t b_hi = r.find(k_hi, b_lo, below_hi);
  const std::size_t m = r.gather(n, b_lo, b_hi, [x](std::size_t i) { return x[i]; });
  // the candidates of the lower bin come first in the order of the values
  const std::size_t r_hi = k_hi - below_hi + (b_hi != b_lo ? r.count[b_lo] : 0);
  lo = selectCandidate(r.cand, m, k_lo - below_lo);
  hi = selectCandidate(r.cand, m, r_hi);
  return true;
}

// max(out, median + k * 1.4826 * MAD) of the finite values of x[0, n) (out unchanged when none
// is finite); false when they need the general path.
RC_SIMD_CLONES bool binnedMedianPlusKMad(const float* x, std::size_t n, float k, BinnedRing& r, float& out)
{
  std::uint32_t lowest;
  if (!binValues(x, n, r.bin, lowest)) return false;
  const std::size_t finite = r.countBins(n);
  if (finite == 0) return true;
  const std::size_t rank = rankOf(finite, 0.5);
  std::size_t below = 0;
  std::uint32_t b = r.findFirst(rank, lowest, below);
  std::size_t m = r.gather(n, b, b, [x](std::size_t i) { return x[i]; });
  const float med = selectCandidate(r.cand, m, rank - below);
  const float lo = deviationBound(r, b, med, rank, false), hi = deviationBound(r, b, med, rank, true);
  std::uint8_t* const flag = r.flag;
  std::uint32_t under = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const float d = std::fabs(x[i] - med);  // NaN: in neither
    under += d < lo ? 1u : 0u;
    flag[i] = static_cast<std::uint8_t>((d >= lo) & (d <= hi));
  }
  below = under;
  m = r.copyFlagged(n, [x, med](std::size_t i) { return std::fabs(x[i] - med); });
  const float mad = selectCandidate(r.cand, m, rank - below);
  out = std::max(med + k * kMadToSigma * mad, out);
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
  scratch_.resize(largest + 1u);  // grown once: no allocation in later frames
  bin_.resize(largest);
  flag_.resize(largest);
  BinnedRing r{bin_.data(), flag_.data(), scratch_.data(), {}};
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

namespace
{
// Edge (2) and Corner (3) are the labels with this bit, Rough (4) and the others are not.
constexpr std::uint8_t kFeatureBit = 2;
inline bool isFeature(Label l) { return (static_cast<std::uint8_t>(l) & kFeatureBit) != 0; }
static_assert(static_cast<int>(Label::Edge) == 2 && static_cast<int>(Label::Corner) == 3 &&
              static_cast<int>(Label::Rough) == 4 && static_cast<int>(Label::Plane) == 1, "see kFeatureBit");

// First k in [u, end) with an Edge or Corner (end if none), eight labels at a time.
std::uint32_t nextFeature(const Label* lab, std::uint32_t u, std::uint32_t end)
{
  constexpr std::uint64_t kBits = 0x0101010101010101ull * kFeatureBit;
  for (; u + 8 <= end; u += 8)
  {
    std::uint64_t w;
    std::memcpy(&w, lab + u, sizeof w);
    if ((w & kBits) == 0) continue;
    // the samples before the first feature of the eight, counted without a branch to mispredict
    std::uint32_t before = 0;
    bool seen = false;
    for (std::uint32_t j = 0; j < 8; ++j)
    {
      seen |= isFeature(lab[u + j]);
      before += seen ? 0 : 1;
    }
    return u + before;
  }
  while (u < end && !isFeature(lab[u])) ++u;
  return u;
}

// Labelling kernels for grid positions [b, b + n): branch-free over raw pointers, so that they
// vectorize (the division and the double product are cheap four or two at a time, and a label
// store would otherwise make the compiler reload every pointer). An ablated feature (paper
// Table 2) reaches them as a threshold no value exceeds. Isolated points stay None.

// Algorithm 1, line by line (NaN compares false, so undefined features fall through).
void labelQuartile(const Features& f, std::size_t b, std::size_t n, const RingThresholds& t, bool use_curvature,
                   Label* label)
{
  const float *const kap = f.curvature.data() + b, *const sm = f.smoothness.data() + b,
              *const dis = f.discontinuity.data() + b;
  std::uint8_t* const lab = reinterpret_cast<std::uint8_t*>(label + b);
  const bool no_curvature = !use_curvature;
  for (std::size_t i = 0; i < n; ++i)
  {
    const float k = kap[i], S = sm[i], D = dis[i];
    const bool edge = use_curvature & (k > t.curvature_high);
    const bool corner = ((k > t.curvature_high) | no_curvature) & (D > t.discontinuity_high);
    const bool plane = ((k < t.curvature_low) | no_curvature) & (D < t.discontinuity_low);
    std::uint8_t l = static_cast<std::uint8_t>(Label::Plane);
    l = edge ? static_cast<std::uint8_t>(Label::Edge) : l;
    l = corner ? static_cast<std::uint8_t>(Label::Corner) : l;
    l = plane ? static_cast<std::uint8_t>(Label::Plane) : l;
    l = S > t.smoothness_high ? static_cast<std::uint8_t>(Label::Rough) : l;
    lab[i] = std::isnan(S) & std::isnan(k) & std::isnan(D) ? static_cast<std::uint8_t>(Label::None) : l;
  }
}

// Robust rules: a turn or a jump counts only above its ring's threshold and above noise.
template <bool kJump>
void labelRobust(const Features& f, const double* range_b, std::size_t b, std::size_t n, const RingThresholds& t,
                 float turn_noise, double jump_noise, Label* label)
{
  const float *const kap = f.curvature.data() + b, *const turning = f.turning.data() + b,
              *const sm = f.smoothness.data() + b, *const dis = f.discontinuity.data() + b;
  const double* const range = range_b + b;
  std::uint8_t* const lab = reinterpret_cast<std::uint8_t*>(label + b);
  for (std::size_t i = 0; i < n; ++i)
  {
    const float k = kap[i], turn = turning[i], S = sm[i], D = dis[i];
    // kappa = turning / chord length, and chord 0 where kappa <= 0: the quotient is masked to
    // +0 by its bits, as the compiler would not vectorize a conditional division (FP traps)
    const float chord = bitsFloat(floatBits(turn / k) & (0u - static_cast<std::uint32_t>(k > 0)));
    // turn > threshold && turn * chord > noise, the product turned into NaN (above nothing)
    // where the first fails: a plain && let the compiler branch around the division
    const float turn_excess = bitsFloat(floatBits(turn * chord) | (turn > t.curvature_high ? 0u : 0x7FC00000u));
    const bool turn_high = turn_excess > turn_noise;
    bool jump_high = D > t.discontinuity_high;
    if (kJump) jump_high = jump_high & (static_cast<double>(D) * range[i] > jump_noise);
    // S is edge-preserving (best one-sided window), so a clean depth jump keeps a low S on
    // its own surface; high S means clutter even where ranges jump everywhere.
    std::uint8_t l = static_cast<std::uint8_t>(Label::Plane);
    l = turn_high ? static_cast<std::uint8_t>(Label::Edge) : l;
    l = jump_high ? static_cast<std::uint8_t>(Label::Corner) : l;
    l = S > t.smoothness_high ? static_cast<std::uint8_t>(Label::Rough) : l;
    lab[i] = std::isnan(S) & std::isnan(k) & std::isnan(D) ? static_cast<std::uint8_t>(Label::None) : l;
  }
}
}  // namespace

void Classifier::suppressNonMaxima(const ScanGrid& grid, const Features& f, std::uint32_t b, std::uint32_t e,
                                   bool closed, std::vector<Label>& labels)
{
  // Keep only the peak turning angle of each run of Edge candidates: a crease seen through
  // chords of h samples lights up h samples on each side of it. Runs are followed around the
  // seam of a closed ring, so a crease on the seam is kept once.
  const std::uint32_t K = e - b;
  if (K == 0) return;
  // Raw pointers: a label store may alias anything, and reloads of the vectors' data pointers
  // after each one kept the loops below from running lean.
  Label* const lab = labels.data() + b;
  const std::uint8_t* const linked = grid.linked.data() + b;
  const float* const turning = f.turning.data() + b;
  // start right after a break (a non-feature sample or a gap) so no run is entered midway
  std::uint32_t start = 0;
  if (closed)
  {
    std::uint32_t k = 0;
    while (k < K && isFeature(lab[k]) && linked[k]) ++k;
    if (k == K) return;  // the whole ring is one run: nothing to compare against
    start = k;
  }
  // The walk visits u = start .. start + K - 1, at sample u or u - K: a wrap-around index
  // instead of a division per sample.
  const std::uint32_t end = start + K;
  auto at = [K](std::uint32_t u) { return u < K ? u : u - K; };
  for (std::uint32_t u = start; u < end;)
  {
    // most samples are no feature: skip them, before the seam and after it
    if (u < K) u = nextFeature(lab, u, std::min(end, K));
    if (u >= K) u = K + nextFeature(lab, u - K, end - K);
    if (u == end) break;
    // the run [u, v)
    std::uint32_t v = u + 1;
    for (; v < end; ++v)
    {
      const std::uint32_t k = at(v);
      if (!isFeature(lab[k]) || !linked[k] || (!closed && k == 0)) break;
    }
    // (branch-free: Edges and Corners, and the turns within a run, come in no predictable order)
    bool touches_corner = false;
    std::uint32_t arg = K;
    float best = -1.0f;
    for (std::uint32_t w = u; w < v; ++w)
    {
      const std::uint32_t k = at(w);
      const bool corner = lab[k] == Label::Corner, better = !corner && turning[k] > best;
      touches_corner |= corner;
      best = better ? turning[k] : best;
      arg = better ? k : arg;
    }
    // a run touching a Corner is the jump's own footprint: the Corner already marks it
    for (std::uint32_t w = u; w < v; ++w)
    {
      const std::uint32_t k = at(w);
      lab[k] = lab[k] == Label::Edge && (k != arg || touches_corner) ? Label::Plane : lab[k];
    }
    u = v;
  }
}

void Classifier::classify(const ScanGrid& grid, const Features& f, const Params& P,
                          const std::vector<RingThresholds>& thr, std::vector<Label>& labels)
{
  labels.assign(grid.size(), Label::None);
  const bool quartile = P.classifier_mode == ClassifierMode::Quartile;
  const float sigma = P.range_noise;
  const float jump_noise = P.noise_floor_k * 2.45f * sigma;  // sqrt(6) sigma: linear-prediction noise
  const float turn_noise = P.noise_floor_k * 2.45f * sigma;  // / chord length, per point below
  const bool jump_mode = P.discontinuity_mode == DiscontinuityMode::Jump;
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    RingThresholds t = thr[static_cast<std::size_t>(n)];
    // ablations (paper Table 2) drop a feature entirely: no value passes its threshold
    if (!P.use_smoothness) t.smoothness_high = kInf;
    if (quartile)
    {
      labelQuartile(f, b, e - b, t, P.use_curvature, labels.data());
      continue;
    }
    if (!P.use_curvature) t.curvature_high = kInf;
    (jump_mode ? labelRobust<true> : labelRobust<false>)(f, grid.range.data(), b, e - b, t, turn_noise,
                                                         static_cast<double>(jump_noise), labels.data());
    if (P.non_max_suppression)
      suppressNonMaxima(grid, f, b, e, grid.ring_closed[static_cast<std::size_t>(n)] != 0, labels);
  }
}

}  // namespace ring_curvature
