// Per-ring thresholds by exact O(K) selection (never a sort): the quantiles of Algorithm 1 and
// the robust median + k MAD, from the histogram where the values allow, else by radix selection.
#include "classification/classifier.hpp"

#include "classification/binned_selection.hpp"
#include "classification/rank_select.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ring_curvature
{

namespace
{
using namespace detail;
constexpr float kDegToRad = 0.0174532925f;
constexpr float kInf = std::numeric_limits<float>::infinity();

// The general path, for rings the bins below cannot order (values with the sign bit set).
// Copies the finite values of v[b, e) to out (room for e - b); returns how many.
std::size_t gatherFinite(const std::vector<float>& v, std::uint32_t b, std::uint32_t e, float* out)
{
  return static_cast<std::size_t>(
      std::copy_if(v.begin() + b, v.begin() + e, out, [](float x) { return std::isfinite(x); }) - out);
}

// median + k * 1.4826 * MAD of buf[0, n) (buf is reordered).
float medianPlusKMad(float* buf, std::size_t n, float k)
{
  const float med = selectQuantile(buf, n, 0.5);
  for (std::size_t i = 0; i < n; ++i) buf[i] = std::fabs(buf[i] - med);
  const float mad = selectQuantile(buf, n, 0.5);
  return med + k * kMadToSigma * mad;
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
