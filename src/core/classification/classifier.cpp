// Labels from the per-ring thresholds (Algorithm 1 and the robust rules) and non-maximum suppression.
#include "classification/classifier.hpp"
#include "common/float_bits.hpp"

#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
using detail::bitsFloat;
using detail::floatBits;

// Edge (2) and Corner (3) are the labels with this bit, Rough (4) and the others are not.
constexpr std::uint8_t kFeatureBit = 2;
inline bool isFeature(Label l) { return (static_cast<std::uint8_t>(l) & kFeatureBit) != 0; }
static_assert(static_cast<int>(Label::Edge) == 2 && static_cast<int>(Label::Corner) == 3 &&
              static_cast<int>(Label::Rough) == 4 && static_cast<int>(Label::Plane) == 1, "see kFeatureBit");

// First k in [u, stop) with an Edge or Corner at k and k + 1 and a link from k to k + 1 (stop if
// none; reads up to index stop), eight samples at a time.
std::uint32_t nextPair(const Label* lab, const std::uint8_t* linked, std::uint32_t u, std::uint32_t stop)
{
  constexpr std::uint64_t kBits = 0x0101010101010101ull * kFeatureBit, kLow7 = 0x7F7F7F7F7F7F7F7Full;
  for (; u + 8 <= stop; u += 8)
  {
    std::uint64_t here, next, link;
    std::memcpy(&here, lab + u, sizeof here);
    std::memcpy(&next, lab + u + 1, sizeof next);
    std::memcpy(&link, linked + u + 1, sizeof link);
    // a byte's top bit set when it is not zero (no carry crosses bytes), moved to bit 1
    const std::uint64_t linked_bits = ((((link & kLow7) + kLow7) | link) >> 6) & kBits;
    const std::uint64_t w = here & next & linked_bits & kBits;
    if (w == 0) continue;
#if defined(__GNUC__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    return u + static_cast<std::uint32_t>(__builtin_ctzll(w)) / 8;  // byte j: bit 8 j + 1
#else
    break;  // the sample loop below finds it
#endif
  }
  while (u < stop && !(isFeature(lab[u]) && isFeature(lab[u + 1]) && linked[u + 1])) ++u;
  return u;
}

// Labelling kernels for positions [b, b + n): branch-free over raw pointers so that they vectorize
// (a label store would otherwise make the compiler reload every pointer). An ablated feature
// (paper Table 2) arrives as a threshold no value exceeds. Isolated points stay None.

// Rough over the label l where S is high, None where no feature is defined.
inline std::uint8_t finalLabel(std::uint8_t l, float k, float S, float D, float smoothness_high)
{
  l = S > smoothness_high ? static_cast<std::uint8_t>(Label::Rough) : l;
  const int undefined =
      static_cast<int>(std::isnan(S)) & static_cast<int>(std::isnan(k)) & static_cast<int>(std::isnan(D));
  return undefined != 0 ? static_cast<std::uint8_t>(Label::None) : l;
}

// Algorithm 1, line by line (NaN compares false, so undefined features fall through).
RC_SIMD_CLONES void labelQuartile(const Features& f, std::size_t b, std::size_t n, const RingThresholds& t, bool use_curvature,
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
    lab[i] = finalLabel(l, k, S, D, t.smoothness_high);
  }
}

// Robust rules: a turn or a jump counts only above its ring's threshold and above noise.
template <bool kJump>
RC_SIMD_CLONES void labelRobust(const Features& f, const double* range_b, std::size_t b, std::size_t n, const RingThresholds& t,
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
    lab[i] = finalLabel(l, k, S, D, t.smoothness_high);
  }
}
}  // namespace

void Classifier::suppressNonMaxima(const ScanGrid& grid, const Features& f, std::uint32_t b, std::uint32_t e,
                                   bool closed, std::vector<Label>& labels)
{
  // Keep only each Edge run's peak turning angle: a crease seen through chords of h samples lights
  // up h samples each side. Runs go around a closed ring's seam, so a crease there is kept once.
  const std::uint32_t K = e - b;
  if (K == 0) return;
  // Raw pointers: a label store may alias anything, so the vectors' data pointers would be reloaded.
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
  // The walk visits u = start .. start + K - 1, at sample u or u - K (no division per sample).
  const std::uint32_t end = start + K;
  auto at = [K](std::uint32_t u) { return u < K ? u : u - K; };
  for (std::uint32_t u = start; u < end;)
  {
    // Most samples are no feature and most runs one sample, which needs nothing (an Edge alone is
    // its own peak; a Corner stays): skip to the first sample followed by one of its run.
    if (u + 1 < K) u = nextPair(lab, linked, u, std::min(end - 1, K - 1));
    if (u == K - 1 && u + 1 < end && !(isFeature(lab[K - 1]) && isFeature(lab[0]) && linked[0])) ++u;
    if (u >= K && u + 1 < end) u = K + nextPair(lab, linked, u - K, end - 1 - K);
    if (u + 1 >= end) break;
    // The run [u, v), walked once, branch-free inside: its Edges become Planes, and the peak (first
    // largest turn among them; none if all NaN) is put back after, unless the run touches a Corner
    // (then it is the jump's footprint, which the Corner already marks).
    bool touches_corner = false;
    std::uint32_t arg = K;
    float best = -1.0f;
    const auto visit = [&](std::uint32_t k) {
      const bool corner = lab[k] == Label::Corner, better = !corner && turning[k] > best;
      touches_corner |= corner;
      best = better ? turning[k] : best;
      arg = better ? k : arg;
      lab[k] = corner ? Label::Corner : Label::Plane;  // a feature: an Edge or a Corner
    };
    visit(at(u));
    // Up to the seam, then past it (an open ring's walk ends at the seam: end = K there).
    std::uint32_t v = u + 1;
    for (const std::uint32_t seam = std::min(end, K); v < seam && isFeature(lab[v]) && linked[v]; ++v) visit(v);
    if (v >= K)
      for (; v < end && isFeature(lab[v - K]) && linked[v - K]; ++v) visit(v - K);
    if (!touches_corner && arg != K) lab[arg] = Label::Edge;
    u = v;
  }
}

void Classifier::classify(const ScanGrid& grid, const Features& f, const Params& P,
                          const std::vector<RingThresholds>& thr, std::vector<Label>& labels)
{
  // No fill first: the rings partition the grid, and each ring's kernel writes all its positions.
  labels.resize(grid.size());
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
