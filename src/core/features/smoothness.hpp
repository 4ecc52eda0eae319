// Smoothness S of Eq 10 along one ring (FeatureComputer::computeRing's last feature), and the
// window statistics its two forms share: prefix sums over the ring (smoothness.cpp) and the
// default mode's small windows from their own samples (smoothness_direct.cpp).
#pragma once

#include "common/ring_index.hpp"

#include <algorithm>
#include <cstddef>

namespace ring_curvature
{

/// Entries of the `prefix` scratch that ringSmoothness needs for a ring of K samples.
inline std::size_t smoothnessScratch(int K, int w, bool closed)
{
  const std::size_t E = static_cast<std::size_t>(K) + 2 * static_cast<std::size_t>(closed ? w : 0);
  return 3 * (E + 1);
}

/// Smoothness of one ring's K samples (window +-w, w >= 1) into out[0, K) from its ranges `rho`, and
/// `rpf` in float padded by w each side; L and R the free links each side (capped above w), seg the
/// segments between gaps, `prefix` room for smoothnessScratch(K, w, closed) values.
void ringSmoothness(int K, int w, bool closed, bool detrend, const double* rho, const float* rpf, const int* L,
                    const int* R, const int* seg, int num_seg, double* prefix, float* out);

namespace detail
{

// Range of ring sample i, i in [-K - 1, 2K] (a closed ring's windows across the seam; an open
// ring's stay inside): the same positions as the features' neighbours across the seam.
inline double wrappedRange(const double* rho, int K, std::ptrdiff_t i)
{
  return rho[wrapRingIndex(i, K)];
}

// 1 / cnt and 1 / (sum (j - jbar)^2 * cnt) for a window of cnt consecutive samples
// (sum (j - jbar)^2 over consecutive j is (cnt^2 - 1) cnt / 12).
inline double invCount(double cnt) { return 1.0 / cnt; }
inline double invTrend(double cnt) { return 1.0 / ((cnt * cnt - 1.0) * cnt * (1.0 / 12.0) * cnt); }

// Residual variance of a window of n samples from the sums of d, (j - jbar) d and d^2, with
// ic = invCount(n) and it = invTrend(n): float in the direct windows, double near a gap.
template <class T>
[[gnu::always_inline]] inline T residualVariance(T s0, T s1, T s2, T ic, T it)
{
  const T mean = s0 * ic;
  return std::max(T(0), s2 * ic - mean * mean - s1 * s1 * it);
}

// Calls f(k) for the samples within w of a segment's ends (seg: the segments' bounds, see
// ringSmoothness), those whose windows a gap cuts short.
template <class F>
[[gnu::always_inline]] inline void forNearGap(int K, int w, const int* seg, int num_seg, const F& f)
{
  for (int i = 0; i + 1 < num_seg; ++i)
  {
    const int p = seg[i], q = seg[i + 1];
    const int a1 = std::max(p, 0), a2 = std::min({p + w, q, K});
    for (int k = a1; k < a2; ++k) f(k);
    const int b1 = std::max({q - w, a1, a2}), b2 = std::min(q, K);
    for (int k = b1; k < b2; ++k) f(k);
  }
}

// The largest window (w) the direct form takes: smaller windows cost less from their own samples
// than from the prefix sums' serial chain.
constexpr int kMaxDirect = 4;

/// Detrended smoothness of a ring's K samples with 2 <= w <= kMaxDirect (see ringSmoothness):
/// full windows in float from `rpf`, the samples near a gap in double from `rho`; ic and it hold
/// invCount and invTrend of every window size up to 2w + 1.
void directRingSmoothness(int K, int w, const double* rho, const float* rpf, const int* L, const int* R,
                          const int* seg, int num_seg, const double* ic, const double* it, float* out);

}  // namespace detail
}  // namespace ring_curvature
