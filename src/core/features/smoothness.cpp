// Smoothness S (Eq 10) along one ring: the residual variance of range over a window of +-w
// samples, from prefix sums over the ring; windows stop at gaps and wrap across the seam of a
// closed ring. The default mode's small windows go to smoothness_direct.cpp.
#include "features/smoothness.hpp"

#include "common/simd_clones.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace ring_curvature
{

namespace
{
using namespace detail;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}  // namespace

RC_SIMD_CLONES void ringSmoothness(int K, int w, bool closed, bool detrend, const double* rho, const float* rpf,
                                   const int* L, const int* R, const int* seg, int num_seg, double* prefix, float* out)
{
  const int ext = closed ? w : 0;
  // 1 / cnt and 1 / (sum (j - jbar)^2 * cnt) per window size (at most 2w + 1) from a small table:
  // no division per window. Windows larger than the table compute them directly.
  constexpr std::size_t kTable = 64;
  double inv_cnt_table[kTable], inv_trend_table[kTable];
  inv_cnt_table[0] = inv_trend_table[0] = 0.0;  // never used: windows hold >= 2 samples
  // Only the sizes a window can have (at most 2w + 1).
  const std::size_t table_end = std::min(kTable, static_cast<std::size_t>(std::max(w, 0)) * 2 + 2);
  for (std::size_t t = 1; t < table_end; ++t)
  {
    const double cnt = static_cast<double>(t);
    inv_cnt_table[t] = invCount(cnt);
    inv_trend_table[t] = t >= 3 ? invTrend(cnt) : 0.0;
  }
  if (detrend && w >= 2 && w <= kMaxDirect)
  {
    directRingSmoothness(K, w, rho, rpf, L, R, seg, num_seg, inv_cnt_table, inv_trend_table, out);
    return;
  }
  // Prefix sums, extended by w each side for closed rings so that windows wrap across the seam.
  const std::size_t E = static_cast<std::size_t>(K) + 2 * static_cast<std::size_t>(ext);
  double* S0 = prefix;                  // sum rho
  double* S1 = S0 + (E + 1);            // sum j * rho
  double* S2 = S1 + (E + 1);            // sum rho^2
  S0[0] = S1[0] = S2[0] = 0.0;
  for (std::size_t e = 0; e < E; ++e)
  {
    const double r = wrappedRange(rho, K, static_cast<std::ptrdiff_t>(e) - ext);
    S0[e + 1] = S0[e] + r;
    S1[e + 1] = S1[e] + static_cast<double>(e) * r;
    S2[e + 1] = S2[e] + r * r;
  }
  // Residual variance of rho over extended indices [lo, hi): plain (Eq 10) or after removing
  // the least-squares line through the window.
  auto windowVar = [&](std::size_t lo, std::size_t hi) -> double {
    const std::size_t n_win = hi - lo;
    const double cnt = static_cast<double>(n_win);
    const bool tabled = n_win < kTable;
    const double inv_cnt = tabled ? inv_cnt_table[n_win] : invCount(cnt);
    const double s0 = S0[hi] - S0[lo], s1 = S1[hi] - S1[lo], s2 = S2[hi] - S2[lo];
    const double mean = s0 * inv_cnt;
    double var = s2 * inv_cnt - mean * mean;  // Eq 10
    if (detrend && n_win >= 3)
    {
      const double jbar = 0.5 * static_cast<double>(lo + hi - 1);
      const double inv_trend = tabled ? inv_trend_table[n_win] : invTrend(cnt);
      const double sjr = s1 - jbar * s0;  // sum (j - jbar) * rho
      var -= sjr * sjr * inv_trend;       // remove the linear trend
    }
    return std::max(0.0, var);
  };
  // Full windows where they fit in the extended ring: the samples left out (an open ring's first
  // and last w) lie near a gap, where shorter windows replace them.
  const int k0 = std::min(std::max(w - ext, 0), K), k1 = std::max(std::min(K + ext - w, K), k0);
  for (int k = k0; k < k1; ++k)
  {
    const auto c0 = static_cast<std::size_t>(k + ext), uw = static_cast<std::size_t>(w);
    double var = windowVar(c0 - uw, c0 + uw + 1);
    if (detrend && w + 1 >= 3)  // edge-preserving: also the two one-sided windows (see below)
      var = std::min({var, windowVar(c0 - uw, c0 + 1), windowVar(c0, c0 + uw + 1)});
    out[k] = static_cast<float>(var);
  }
  forNearGap(K, w, seg, num_seg, [&](int k) __attribute__((always_inline)) {
    const int a = std::min(w, L[k]), z = std::min(w, R[k]);  // reach of the window, left / right
    const std::size_t c0 = static_cast<std::size_t>(k + ext);
    const std::size_t lo = c0 - static_cast<std::size_t>(a);
    const std::size_t hi = c0 + static_cast<std::size_t>(z) + 1;  // exclusive
    if (hi - lo < 2)
    {
      out[k] = hi - lo == 1 ? 0.0f : kNaN;
      return;
    }
    double var = windowVar(lo, hi);
    if (detrend)
    {
      // Edge-preserving: beside a crease one side lies on a single face, so the best of the three
      // windows is high only where every window is rough (vegetation, clutter).
      if (c0 + 1 - lo >= 3) var = std::min(var, windowVar(lo, c0 + 1));
      if (hi - c0 >= 3) var = std::min(var, windowVar(c0, hi));
    }
    out[k] = static_cast<float>(var);
  });
}

}  // namespace ring_curvature
