// Ring-wise features. Every ring is processed as a chain of runs (maximal gap-free stretches);
// no feature reaches across a gap, and a closed ring wraps across the 0/360 deg seam.
#include "features/feature_computer.hpp"
#include "common/float_bits.hpp"

#include "common/angles.hpp"
#include "features/ring_kernels.hpp"
#include "features/smoothness.hpp"
#include "common/grow.hpp"
#include "common/ring_index.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
using namespace detail;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Run lengths of the samples of segment [p, q) of a ring (see ringRuns), those in [0, K).
inline void segmentRuns(int p, int q, int K, int cap, int* __restrict L, int* __restrict R)
{
  const int k0 = std::max(p, 0), k1 = std::min(q, K);
  for (int k = k0; k < k1; ++k)
  {
    L[k] = std::min(k - p, cap);
    R[k] = std::min(q - 1 - k, cap);
  }
}

// Arc length of the step from grid position pp to pk on the cone (Eq 6, midpoint rule), with
// the step's range difference in dr.
inline double coneStep(const ScanGrid& g, std::uint32_t pp, std::uint32_t pk, double dth, double cone_cos, double& dr)
{
  dr = g.range[pk] - g.range[pp];
  const double rbar = 0.5 * (g.range[pk] + g.range[pp]);
  return std::sqrt(dr * dr + (rbar * cone_cos * dth) * (rbar * cone_cos * dth));
}

// Azimuth of grid position pj seen from pk: from the stored azimuths, or `exact` from the
// coordinates (the paper and developed modes).
inline double relAngle(const ScanGrid& g, std::uint32_t pk, std::uint32_t pj, bool exact)
{
  if (!exact) return wrapPi(static_cast<double>(g.azimuth[pj]) - g.azimuth[pk]);
  const double xk = g.x[pk], yk = g.y[pk], xj = g.x[pj], yj = g.y[pj];
  return std::atan2(xk * yj - yk * xj, xk * xj + yk * yj);
}
}  // namespace

const char* coreLoopsIsa()
{
  // target_clones picks the AVX2 clones of the hot loops at load time (simd_clones.hpp)
#if defined(RC_SIMD_CLONES_ON)
  return __builtin_cpu_supports("avx2") ? "avx2 clones" : "baseline";
#else
  return "portable";
#endif
}

void FeatureComputer::compute(const ScanGrid& grid, const Params& params, Features& out)
{
  // No NaN fill of the whole arrays first: computeRing writes every position of its ring.
  const std::size_t m = grid.size();
  out.curvature.resize(m);
  out.turning.resize(m);
  out.smoothness.resize(m);
  out.discontinuity.resize(m);
  for (int n = 0; n < grid.num_rings; ++n) computeRing(grid, params, n, out);
}

void FeatureComputer::computeRing(const ScanGrid& g, const Params& P, int n, Features& out)
{
  const RingSpan R(g, n);
  if (R.K < 2)
  {
    for (auto* v : {&out.curvature, &out.turning, &out.smoothness, &out.discontinuity})
      std::fill(v->begin() + R.b, v->begin() + R.b + R.K, kNaN);
    return;
  }
  const int cap = std::max({P.max_chord_samples, P.smoothness_window, 2}) + 1;
  const int num_seg = ringRuns(g, n, cap);
  padRing(g, n, cap);
  if (P.curvature_mode == CurvatureMode::Chord)
    chordCurvature(g, P, n, out);
  else
    developedCurvature(g, P, n, out);
  discontinuity(g, P, n, out);
  const int* const L = runs_.data();
  growTo(prefix_, smoothnessScratch(static_cast<int>(R.K), P.smoothness_window, R.closed));
  ringSmoothness(static_cast<int>(R.K), P.smoothness_window, R.closed, P.smoothness_mode == SmoothnessMode::Detrended,
                 g.range.data() + R.b, rho_pad_f_.data() + cap_, L, L + R.K, seg_.data(), num_seg, prefix_.data(),
                 out.smoothness.data() + R.b);
}

// seg[i] is segment i's first sample (linked[k] = 0, or a virtual start before the seam), seg[i + 1]
// its end; in [p, q), L[k] = min(k - p, cap), R[k] = min(q - 1 - k, cap). A closed ring's runs go
// on across the seam (a walk of at most `cap` links each way). The smoothness reuses the list.
int FeatureComputer::ringRuns(const ScanGrid& g, int n, int cap)
{
  const RingSpan S(g, n);
  const std::uint32_t K = S.K;
  growTo(runs_, 2 * static_cast<std::size_t>(K));
  int* const L = runs_.data();
  int* const R = runs_.data() + K;
  const std::uint8_t* const lk = g.linked.data() + S.b;
  growTo(seg_, static_cast<std::size_t>(K) + 2);
  int* const seg = seg_.data();
  int num_seg = 0;
  int run = 0;
  if (S.closed)
    for (std::uint32_t j = K; j-- > 0 && lk[j] != 0 && run < cap;) ++run;
  seg[num_seg++] = -run - 1;
  for (const std::uint8_t* z = lk;
       (z = static_cast<const std::uint8_t*>(std::memchr(z, 0, static_cast<std::size_t>(lk + K - z)))) != nullptr; ++z)
    seg[num_seg++] = static_cast<int>(z - lk);
  run = 0;
  if (S.closed)
    for (std::uint32_t j = 1; j <= K && lk[j == K ? 0 : j] != 0 && run < cap; ++j) ++run;
  seg[num_seg++] = S.closed && lk[0] != 0 ? static_cast<int>(K) + run + 1 : static_cast<int>(K);
  for (int i = 0; i + 1 < num_seg; ++i) segmentRuns(seg[i], seg[i + 1], static_cast<int>(K), cap, L, R);
  return num_seg;
}

// The ring's azimuths and float ranges padded by `cap` samples each side (a closed ring's neighbours
// across the seam; unused copies for an open one), so neighbour k + j is azp[k + j], no wrap.
void FeatureComputer::padRing(const ScanGrid& g, int n, int cap)
{
  const RingSpan S(g, n);
  const std::uint32_t K = S.K, b = S.b;
  cap_ = cap;
  growTo(az_pad_, K + 2 * static_cast<std::size_t>(cap));
  growTo(rho_pad_f_, K + 2 * static_cast<std::size_t>(cap));
  float* const azp = az_pad_.data() + cap;
  float* const rpf = rho_pad_f_.data() + cap;
  std::copy(g.azimuth.begin() + b, g.azimuth.begin() + b + K, azp);
  const double* const rho = g.range.data() + b;
  for (std::uint32_t k = 0; k < K; ++k) rpf[k] = static_cast<float>(rho[k]);
  const auto padFrom = [&](std::int64_t k) {
    return S.closed ? S.pos(k) : b + static_cast<std::uint32_t>(std::clamp<std::int64_t>(k, 0, K - 1));
  };
  for (std::int64_t j = 1; j <= cap; ++j)
  {
    const std::int64_t lo = -j, hi = static_cast<std::int64_t>(K) - 1 + j;
    rpf[lo] = static_cast<float>(g.range[padFrom(lo)]);
    azp[lo] = g.azimuth[padFrom(lo)];
    rpf[hi] = static_cast<float>(g.range[padFrom(hi)]);
    azp[hi] = g.azimuth[padFrom(hi)];
  }
}

// Chord mode, in float, in loops that vectorize (fastAtan2 is branch-free; -fno-math-errno). If an
// angle exceeded the polynomial's range, the ring's chords are formed again with libm.
RC_SIMD_CLONES void FeatureComputer::chordCurvature(const ScanGrid& g, const Params& P, int n, Features& out)
{
  const RingSpan S(g, n);
  const std::uint32_t K = S.K;
  const int Ki = static_cast<int>(K);
  const int* const L = runs_.data();
  const int* const Rr = L + K;
  const float* const azp = az_pad_.data() + cap_;
  const float* const rpf = rho_pad_f_.data() + cap_;
  const float res = std::max(1e-6f, g.azimuth_resolution);
  const float cf = g.ring_cos[static_cast<std::size_t>(n)];
  growTo(half_, K);
  growTo(chord_, 4 * static_cast<std::size_t>(K));
  int* const H = half_.data();
  float* const CROSS = chord_.data();  // the chords' cross and dot products, squared lengths
  float* const DOT = CROSS + K;
  float* const V2 = DOT + K;
  float* const U2 = V2 + K;
  chordSamples(Ki, rpf, cf, res, P.chord_length, P.max_chord_samples, H);
  if (chordProducts(Ki, cf, H, L, Rr, azp, rpf, CROSS, DOT, V2, U2, false))
    chordProducts(Ki, cf, H, L, Rr, azp, rpf, CROSS, DOT, V2, U2, true);
  float* const turning = out.turning.data() + S.b;
  float* const curvature = out.curvature.data() + S.b;
  for (std::uint32_t k = 0; k < K; ++k)
  {
    const float turn = std::fabs(fastAtan2(CROSS[k], DOT[k]));
    const float len = 0.5f * (std::sqrt(V2[k]) + std::sqrt(U2[k]));
    storeCurvature(turn, len, (L[k] != 0) & (Rr[k] != 0), turning[k], curvature[k]);
  }
}

// The paper's (Eq 6-9) and the developed mode, in double: each neighbour developed around the
// vertex (w_k = (rho_k, 0)), the turning angle between the chords to the two neighbours and the
// cone-metric arc length of the incoming step.
void FeatureComputer::developedCurvature(const ScanGrid& g, const Params& P, int n, Features& out)
{
  const RingSpan S(g, n);
  const std::uint32_t K = S.K, b = S.b;
  const int* const L = runs_.data();
  const int* const Rr = L + K;
  const double c = P.curvature_mode == CurvatureMode::Paper ? 1.0 : g.ring_cos[static_cast<std::size_t>(n)];
  const double cone_cos = g.ring_cos[static_cast<std::size_t>(n)];
  const double* const rho = g.range.data() + b;
  const auto develop = [&](std::uint32_t pk, std::uint32_t pj, double& wx, double& wy) {
    double s, co;
    smallSinCos(c * relAngle(g, pk, pj, true), s, co);
    wx = g.range[pj] * co;
    wy = g.range[pj] * s;
  };
  growTo(turn_len_, 2 * static_cast<std::size_t>(K));
  double* const TURN = turn_len_.data();
  double* const LEN = TURN + K;
  for (std::uint32_t k = 0; k < K; ++k)
  {
    if (L[k] == 0 || Rr[k] == 0) continue;  // turning angle needs a neighbour on each side
    const std::uint32_t pk = b + k;
    const std::uint32_t pp = S.pos(static_cast<std::int64_t>(k) - 1);
    const std::uint32_t pn = S.pos(static_cast<std::int64_t>(k) + 1);
    double ax, ay, cx, cy;
    develop(pk, pp, ax, ay);
    develop(pk, pn, cx, cy);
    const double vx = rho[k] - ax, vy = -ay;  // incoming chord
    const double ux = cx - rho[k], uy = cy;   // outgoing chord
    TURN[k] = std::fabs(std::atan2(vx * uy - vy * ux, vx * ux + vy * uy));
    // Eq 6: cone-metric arc length of the incoming step (midpoint rule); Eq 9 divides by it.
    double dr;
    LEN[k] = coneStep(g, pp, pk, relAngle(g, pp, pk, true), cone_cos, dr);
  }
  float* const turning = out.turning.data() + b;
  float* const curvature = out.curvature.data() + b;
  for (std::uint32_t k = 0; k < K; ++k)
    storeCurvature(TURN[k], LEN[k], (L[k] != 0) & (Rr[k] != 0), turning[k], curvature[k]);
}

void FeatureComputer::discontinuity(const ScanGrid& g, const Params& P, int n, Features& out)
{
  const RingSpan S(g, n);
  const std::uint32_t K = S.K;
  const int* const L = runs_.data();
  const int* const Rr = L + K;
  if (P.discontinuity_mode == DiscontinuityMode::Jump)
  {
    // Link (k-1, k): the smaller relative misprediction of each side's linear extrapolation (a
    // grazing plane is predicted well from both sides, a depth jump from neither); a point takes
    // its larger link. jump[K] repeats jump[0] (a closed ring's seam) so largerLink needs no wrap.
    growTo(jump_, K + 1);
    linkJumps(static_cast<int>(K), L, Rr, rho_pad_f_.data() + cap_, jump_.data());
    jump_[K] = jump_[0];
    largerLink(static_cast<int>(K), Rr, jump_.data(), out.discontinuity.data() + S.b);
    return;
  }
  // Eq 11: |d rho| / ds of the incoming step
  const bool exact = P.curvature_mode != CurvatureMode::Chord;
  const double cone_cos = g.ring_cos[static_cast<std::size_t>(n)];
  for (std::uint32_t k = 0; k < K; ++k)
  {
    const std::uint32_t pk = S.b + k;
    if (L[k] == 0)
    {
      out.discontinuity[pk] = kNaN;
      continue;
    }
    const std::uint32_t pp = S.pos(static_cast<std::int64_t>(k) - 1);
    double dr;
    const double ds = coneStep(g, pp, pk, relAngle(g, pp, pk, exact), cone_cos, dr);
    out.discontinuity[pk] = ds > 0 ? static_cast<float>(std::fabs(dr) / ds) : 0.0f;
  }
}

}  // namespace ring_curvature
