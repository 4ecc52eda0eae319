// Smoothness S (Eq 10) along one ring: the residual variance of range over a window of +-w
// samples, from prefix sums over the ring; windows stop at gaps and wrap across the seam of a
// closed ring. The default mode's small windows go to smoothness_direct.cpp.
#include "features/smoothness.hpp"

#include "features/smoothness_windows.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
using namespace detail;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The largest smoothness_window that Params::validate lets through.
constexpr int kMaxWindow = 256;

// The (detrended) variance of extended indices [lo, hi) from the prefix sums S0 (rho), S1 (j rho),
// S2 (rho^2); jbar is the window's mean index, 0.5 * (lo + hi - 1).
inline double windowVariance(const double* S0, const double* S1, const double* S2, bool detrend, int lo, int hi,
                             double jbar, double inv_cnt, double inv_trend)
{
  const double s0 = S0[hi] - S0[lo], s1 = S1[hi] - S1[lo], s2 = S2[hi] - S2[lo];
  const double mean = s0 * inv_cnt;
  double v = s2 * inv_cnt - mean * mean;  // Eq 10
  const double sjr = s1 - jbar * s0;            // sum (j - jbar) * rho
  v = detrend ? v - sjr * sjr * inv_trend : v;  // remove the linear trend
  return std::max(0.0, v);
}

// One sample's full windows (centred; detrended, also the two one-sided). Bounds are clamped into
// [0, E] only for an open ring's first and last w samples (near a gap the caller overwrites); the
// middle loop passes them unclamped so that the compiler sees contiguous loads, not gathers.
template <bool kClamp>
inline float fullWindowSample(int k, int w, int ext, bool detrend, bool sided, int E, const double* __restrict S0,
                              const double* __restrict S1, const double* __restrict S2, double ic, double it,
                              double ics, double its)
{
  const int c0 = k + ext;
  const int lo = kClamp ? std::max(c0 - w, 0) : c0 - w;
  const int hi = kClamp ? std::min(c0 + w + 1, E) : c0 + w + 1;
  const int mid = kClamp ? std::min(c0 + 1, E) : c0 + 1;
  // Mean indices: unclamped, 0.5 * (lo + hi - 1) is c0 for the centred window and c0 -+ w / 2
  // for the one-sided ones, exactly (multiples of 0.5 far below 2^52): one conversion, not three.
  const double dc = static_cast<double>(c0), hw = 0.5 * static_cast<double>(w);
  const auto jbar = [](int a, int z) { return 0.5 * static_cast<double>(a + z - 1); };
  double v = windowVariance(S0, S1, S2, detrend, lo, hi, kClamp ? jbar(lo, hi) : dc, ic, it);
  if (sided)
  {
    v = std::min(v, windowVariance(S0, S1, S2, true, lo, mid, kClamp ? jbar(lo, mid) : dc - hw, ics, its));
    v = std::min(v, windowVariance(S0, S1, S2, true, c0, hi, kClamp ? jbar(c0, hi) : dc + hw, ics, its));
  }
  return static_cast<float>(v);
}

// Samples whose windows need no clamp: c0 - w >= 0 and c0 + w + 1 <= E (all of a closed ring).
inline void unclampedRange(int K, int w, int ext, int& k0, int& k1)
{
  k0 = std::min(std::max(w - ext, 0), K);
  k1 = std::max(std::min(K + ext - w, K), k0);
}

// Detrended (w + 1 >= 3): the centred and the two one-sided windows. Two functions rather than
// one with a lambda or template: the loops must be compiled inside the AVX2 clone.
RC_SIMD_CLONES void fullWindowSmoothnessSided(int K, int w, int ext, int E, const double* __restrict S0,
                                                   const double* __restrict S1, const double* __restrict S2,
                                                   float* __restrict out)
{
  const double nc = 2.0 * w + 1.0, ns = w + 1.0;
  const double ic = invCount(nc), it = invTrend(nc), ics = invCount(ns), its = invTrend(ns);
  int k0, k1;
  unclampedRange(K, w, ext, k0, k1);
  for (int k = 0; k < k0; ++k) out[k] = fullWindowSample<true>(k, w, ext, true, true, E, S0, S1, S2, ic, it, ics, its);
  // Unclamped, sample k's left window is sample k - w's right one with the same mean index (exact):
  // the same operations on the same values, so each one-sided window is formed once, a block at a
  // time. (Windows wider than Params::validate allows take the per-sample loop.)
  constexpr int kBlock = 256;
  double sided[kBlock + kMaxWindow];
  const double hw = 0.5 * static_cast<double>(w);
  if (w > kMaxWindow)
    for (int k = k0; k < k1; ++k)
      out[k] = fullWindowSample<false>(k, w, ext, true, true, E, S0, S1, S2, ic, it, ics, its);
  for (int kb = w > kMaxWindow ? k1 : k0; kb < k1; kb += kBlock)
  {
    const int ke = std::min(kb + kBlock, k1);
    const int j0 = kb + ext - w;  // sided[t]: the window [j0 + t, j0 + t + w + 1)
    for (int t = 0; t < ke - kb + w; ++t)
    {
      const int j = j0 + t;
      sided[t] = windowVariance(S0, S1, S2, true, j, j + w + 1, static_cast<double>(j) + hw, ics, its);
    }
    for (int k = kb; k < ke; ++k)
    {
      const int c0 = k + ext;
      double v = windowVariance(S0, S1, S2, true, c0 - w, c0 + w + 1, static_cast<double>(c0), ic, it);
      v = std::min(v, sided[k - kb]);      // left: [c0 - w, c0 + 1)
      v = std::min(v, sided[k - kb + w]);  // right: [c0, c0 + w + 1)
      out[k] = static_cast<float>(v);
    }
  }
  for (int k = k1; k < K; ++k) out[k] = fullWindowSample<true>(k, w, ext, true, true, E, S0, S1, S2, ic, it, ics, its);
}

// The centred window alone (plain, or detrended with w + 1 < 3).
RC_SIMD_CLONES void fullWindowSmoothnessCentred(int K, int w, int ext, bool detrend, int E,
                                                     const double* __restrict S0, const double* __restrict S1,
                                                     const double* __restrict S2, float* __restrict out)
{
  const double nc = 2.0 * w + 1.0;
  const double ic = invCount(nc), it = invTrend(nc);
  int k0, k1;
  unclampedRange(K, w, ext, k0, k1);
  for (int k = 0; k < k0; ++k) out[k] = fullWindowSample<true>(k, w, ext, detrend, false, E, S0, S1, S2, ic, it, 0, 0);
  for (int k = k0; k < k1; ++k)
    out[k] = fullWindowSample<false>(k, w, ext, detrend, false, E, S0, S1, S2, ic, it, 0, 0);
  for (int k = k1; k < K; ++k) out[k] = fullWindowSample<true>(k, w, ext, detrend, false, E, S0, S1, S2, ic, it, 0, 0);
}

// The samples near a gap (the first and last w of each segment; w < cap) with shorter windows;
// windowVar(lo, hi) is the (detrended) variance of extended indices [lo, hi).
template <class WindowVar>
[[gnu::always_inline]] inline void nearGapSmoothness(int K, int w, int ext, const int* seg, int num_seg, const int* L,
                                                     const int* R, float* out, const WindowVar& windowVar, bool detrend)
{
  // Inlined by force: out of line it would be a baseline call per sample from the AVX2 clone.
  const auto nearGap = [&](std::uint32_t k) __attribute__((always_inline)) {
    const int a = std::min(w, L[k]), z = std::min(w, R[k]);  // reach of the window, left / right
    const std::size_t c0 = k + static_cast<std::size_t>(ext);
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
  };
  for (int i = 0; i + 1 < num_seg; ++i)
  {
    const int p = seg[i], q = seg[i + 1];
    const int a1 = std::max(p, 0), a2 = std::min({p + w, q, K});
    for (int k = a1; k < a2; ++k) nearGap(static_cast<std::uint32_t>(k));
    const int b1 = std::max({q - w, a1, a2}), b2 = std::min(q, K);
    for (int k = b1; k < b2; ++k) nearGap(static_cast<std::uint32_t>(k));
  }
}

inline void fullWindowSmoothness(int K, int w, int ext, bool detrend, int E, const double* S0, const double* S1,
                                 const double* S2, float* out)
{
  if (detrend && w + 1 >= 3)
    fullWindowSmoothnessSided(K, w, ext, E, S0, S1, S2, out);
  else
    fullWindowSmoothnessCentred(K, w, ext, detrend, E, S0, S1, S2, out);
}
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
  // every entry of `prefix` but the three leading zeros is written below
  double* S0 = prefix;                  // sum rho
  double* S1 = S0 + (E + 1);            // sum j * rho
  double* S2 = S1 + (E + 1);            // sum rho^2
  S0[0] = S1[0] = S2[0] = 0.0;
  {
    // Running sums in registers (same additions, same order): through the arrays, which may alias
    // rho, each step would wait on the store before. The index as a double counter (exact: E < 2^53).
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, ed = 0.0;
    // An open ring's ranges are summed in place; a closed ring's with w neighbours across the
    // seam on each side, copied after the sums' arrays.
    const double* rs = rho;
    if (ext > 0)
    {
      double* const pad = S2 + (E + 1);
      const std::size_t x = static_cast<std::size_t>(ext);
      for (std::size_t e = 0; e < x; ++e) pad[e] = wrappedRange(rho, K, static_cast<std::ptrdiff_t>(e) - ext);
      std::copy(rho, rho + K, pad + x);
      for (std::size_t e = x + static_cast<std::size_t>(K); e < E; ++e)
        pad[e] = wrappedRange(rho, K, static_cast<std::ptrdiff_t>(e) - ext);
      rs = pad;
    }
    std::size_t e = 0;
    // Two samples a step, each array's pair in one 16-byte store (the stores bound the loop); the
    // second sample's sums are the first's plus its terms, as in the loop below.
    using Pair = double __attribute__((vector_size(16)));
    for (; e + 2 <= E; e += 2, ed += 2.0)
    {
      const double r = rs[e], q = rs[e + 1];
      const double a0 = s0 + r, a1 = s1 + ed * r, a2 = s2 + r * r;
      s0 = a0 + q;
      s1 = a1 + (ed + 1.0) * q;
      s2 = a2 + q * q;
      const Pair p0 = {a0, s0}, p1 = {a1, s1}, p2 = {a2, s2};
      std::memcpy(S0 + e + 1, &p0, sizeof p0);
      std::memcpy(S1 + e + 1, &p1, sizeof p1);
      std::memcpy(S2 + e + 1, &p2, sizeof p2);
    }
    for (; e < E; ++e, ed += 1.0)
    {
      const double r = rs[e];
      s0 += r;
      s1 += ed * r;
      s2 += r * r;
      S0[e + 1] = s0;
      S1[e + 1] = s1;
      S2[e + 1] = s2;
    }
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
      // sum (j - jbar)^2 over consecutive j is (cnt^2 - 1) cnt / 12
      const double inv_trend = tabled ? inv_trend_table[n_win] : invTrend(cnt);
      const double sjr = s1 - jbar * s0;  // sum (j - jbar) * rho
      var -= sjr * sjr * inv_trend;       // remove the linear trend
    }
    return std::max(0.0, var);
  };
  // Full windows for every sample in a straight loop that vectorizes, then those near a gap redone
  // with shorter windows. Same operations on the same values (the tables hold exactly the factors).
  fullWindowSmoothness(K, w, ext, detrend, static_cast<int>(E), S0, S1, S2, out);
  nearGapSmoothness(K, w, ext, seg, num_seg, L, R, out, windowVar, detrend);
}

}  // namespace ring_curvature
