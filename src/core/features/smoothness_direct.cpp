// The default mode's smoothness (Detrended, w <= kMaxDirect): each sample's windows from their
// own samples, without prefix sums.
#include "features/smoothness.hpp"

#include "common/simd_clones.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace ring_curvature
{
namespace detail
{
namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Detrended smoothness of every sample from its own window in float (w <= kMaxDirect): sums of
// d_j = rho_{k+j} - rho_k, not of ranges, so the variance's cancellation works at the size of the
// window's range differences (error ~1e-7 of that spread, as float32 input carries anyway).

template <int W>
[[gnu::always_inline]] inline void directWindows(int K, const float* __restrict rp, float* __restrict out)
{
  // 1 / n and 1 / (n sum (j - jbar)^2) for the centred window (2W + 1) and the sided ones (W + 1)
  const float ic = 1.0f / (2 * W + 1), ics = 1.0f / (W + 1);
  const float it = static_cast<float>(invTrend(2.0 * W + 1.0)), its = static_cast<float>(invTrend(W + 1.0));
  constexpr float half = 0.5f * W;
  for (int k = 0; k < K; ++k)
  {
    float l0 = 0, l1 = 0, l2 = 0, r0 = 0, r1 = 0, r2 = 0;
    for (int j = 1; j <= W; ++j)
    {
      const float dl = rp[k - j] - rp[k], dr = rp[k + j] - rp[k];
      l0 += dl;
      r0 += dr;
      l1 += static_cast<float>(j) * dl;  // sum j d over the left side (indices -j)
      r1 += static_cast<float>(j) * dr;
      l2 += dl * dl;
      r2 += dr * dr;
    }
    // centred window: index -j on the left, +j on the right, mean index 0
    float v = residualVariance(l0 + r0, r1 - l1, l2 + r2, ic, it);
    // sided windows (the centre sample's d is 0): indices -W..0 and 0..W, mean -+W/2
    v = std::min(v, residualVariance(l0, half * l0 - l1, l2, ics, its));
    v = std::min(v, residualVariance(r0, r1 - half * r0, r2, ics, its));
    out[k] = v;
  }
}

RC_SIMD_CLONES void directSmoothness(int K, int w, const float* __restrict rp, float* __restrict out)
{
  switch (w)
  {
    case 2: directWindows<2>(K, rp, out); break;
    case 3: directWindows<3>(K, rp, out); break;
    default: directWindows<4>(K, rp, out); break;
  }
}

// Sums over a window at(0) .. at(n - 1) relative to its first: of d, (j - jbar) d and d^2 (the
// near-gap windows, in double); addWindowSample adds one sample's terms.
[[gnu::always_inline]] inline void addWindowSample(double d, std::size_t j, double jbar, double& s0, double& s1,
                                                   double& s2)
{
  s0 += d;
  s1 += (static_cast<double>(j) - jbar) * d;
  s2 += d * d;
}
template <class At>
[[gnu::always_inline]] inline void windowSums(std::size_t n, double& s0, double& s1, double& s2, At at)
{
  const double ref = at(0), jbar = 0.5 * static_cast<double>(n - 1);
  s0 = s1 = s2 = 0;
  for (std::size_t j = 0; j < n; ++j) addWindowSample(at(j) - ref, j, jbar, s0, s1, s2);
}
// nearGapDirect's sums, and of the first n_left samples the sum of (j - jbar_l) d: the left window's
// sums of d and d^2 are the whole's after n_left steps (the same additions in the same order).
template <class At>
[[gnu::always_inline]] inline void sharedWindowSums(std::size_t n_all, std::size_t n_left, double* all, double* left,
                                                    At at)
{
  const double ref = at(0), jbar = 0.5 * static_cast<double>(n_all - 1);
  const double jbar_l = 0.5 * static_cast<double>(n_left - 1);
  double s0 = 0, s1 = 0, s2 = 0, s1l = 0;
  std::size_t j = 0;
  for (; j < n_left; ++j)
  {
    const double d = at(j) - ref;
    addWindowSample(d, j, jbar, s0, s1, s2);
    s1l += (static_cast<double>(j) - jbar_l) * d;
  }
  left[0] = s0;
  left[1] = s1l;
  left[2] = s2;
  for (; j < n_all; ++j) addWindowSample(at(j) - ref, j, jbar, s0, s1, s2);
  all[0] = s0;
  all[1] = s1;
  all[2] = s2;
}

// The near-gap windows of the direct form, in double, relative to each window's first sample:
// centred and left windows in one pass; a one-sided window equal to the centred one is not formed
// again (min(v, v) is v).
inline void nearGapDirect(int K, int w, const int* seg, int num_seg, const int* L, const int* R, const double* rho,
                          const double* ic, const double* it, float* out)
{
  const auto nearGap = [&](int k) __attribute__((always_inline)) {
    const int a = std::min(w, L[k]), z = std::min(w, R[k]);  // reach of the window, left / right
    const std::size_t n = static_cast<std::size_t>(a + z + 1), n_left = static_cast<std::size_t>(a + 1);
    if (n < 2)
    {
      out[k] = n == 1 ? 0.0f : kNaN;
      return;
    }
    const std::ptrdiff_t first = k - a;  // ring sample of the window's first
    // ring sample first + j, across the seam of a closed ring
    const auto at = [&](std::ptrdiff_t from) {
      return [=](std::size_t j) { return wrappedRange(rho, K, from + static_cast<std::ptrdiff_t>(j)); };
    };
    double all[3], left[3];
    sharedWindowSums(n, n_left, all, left, at(first));
    double var = residualVariance(all[0], all[1], all[2], ic[n], it[n]);
    if (n_left >= 3 && z > 0)
      var = std::min(var, residualVariance(left[0], left[1], left[2], ic[n_left], it[n_left]));
    const std::size_t n_right = static_cast<std::size_t>(z + 1);
    if (n_right >= 3 && a > 0)
    {
      double s0, s1, s2;
      windowSums(n_right, s0, s1, s2, at(k));
      var = std::min(var, residualVariance(s0, s1, s2, ic[n_right], it[n_right]));
    }
    out[k] = static_cast<float>(var);
  };
  forNearGap(K, w, seg, num_seg, nearGap);
}
}  // namespace

RC_SIMD_CLONES void directRingSmoothness(int K, int w, const double* rho, const float* rpf, const int* L,
                                         const int* R, const int* seg, int num_seg, const double* ic,
                                         const double* it, float* out)
{
  directSmoothness(K, w, rpf, out);
  nearGapDirect(K, w, seg, num_seg, L, R, rho, ic, it, out);
}

}  // namespace detail
}  // namespace ring_curvature
