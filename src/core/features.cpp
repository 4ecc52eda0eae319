// Ring-wise features. Every ring is processed as a chain of runs (maximal gap-free stretches);
// no feature reaches across a gap, and a closed ring wraps across the 0/360 deg seam.
#include "ring_curvature/features.hpp"

#include "angles.hpp"
#include "cpu_tuning.hpp"
#include "grow.hpp"
#include "ring_index.hpp"
#include "simd_clones.hpp"
#include "smoothness.hpp"
#include "vertical_pairs.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace ring_curvature
{

namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// sin / cos of the small angles between ring neighbours (|a| < 0.2 rad almost always): a
// Taylor polynomial is exact to ~1e-12 there and far cheaper than the libm calls.
constexpr double kSmallAngle = 0.2;
template <class T>
inline void polySinCos(T a, T& s, T& c)
{
  // Reciprocal constants: without -ffast-math a "/ 6.0" stays a division, and these six were
  // the largest cost of the feature stage (perf); the result differs by an ulp at most.
  const T a2 = a * a;
  s = a * (T(1) - a2 * T(1.0 / 6.0) * (T(1) - a2 * T(1.0 / 20.0) * (T(1) - a2 * T(1.0 / 42.0))));
  c = T(1) - a2 * T(0.5) * (T(1) - a2 * T(1.0 / 12.0) * (T(1) - a2 * T(1.0 / 30.0)));
}
template <class T>
inline void smallSinCos(T a, T& s, T& c)
{
  if (std::fabs(a) > static_cast<T>(kSmallAngle))
  {
    s = std::sin(a);
    c = std::cos(a);
    return;
  }
  polySinCos(a, s, c);
}

// One sample's chords from its own azimuth and range and its two chord ends' (p: incoming, n:
// outgoing); returns 1 when an angle exceeded the polynomial's range. Shared by the kernel that
// reads the ends through their indices and the one that reads them gathered (chordEndsAvx512),
// so that both form the same operations.
template <class SinCos>
inline int chordSample(float c, float az_k, float rho_k, float az_p, float rho_p, float az_n, float rho_n,
                       SinCos sinCos, float& cross, float& dot, float& v2, float& u2)
{
  constexpr float small = static_cast<float>(kSmallAngle);
  const float ap = c * wrapPi(az_p - az_k), an = c * wrapPi(az_n - az_k);
  const int large = (std::fabs(ap) > small ? 1 : 0) | (std::fabs(an) > small ? 1 : 0);
  float sp, cp, sn, cn;
  sinCos(ap, sp, cp);
  sinCos(an, sn, cn);
  const float vx = rho_k - rho_p * cp, vy = -(rho_p * sp);  // incoming chord
  const float ux = rho_n * cn - rho_k, uy = rho_n * sn;     // outgoing chord
  cross = vx * uy - vy * ux;
  dot = vx * ux + vy * uy;
  v2 = vx * vx + vy * vy;
  u2 = ux * ux + uy * uy;
  return large;
}
// Chord mode's developed chords from vertex k to k - min(H, L) and k + min(H, R), on the padded
// ring arrays (`az`, `rho` indexed from -pad): their cross and dot products and squared
// lengths. Where a side has no neighbour the reach is 0 and the chord degenerates to the vertex
// itself (harmless values the caller never stores). The sine and cosine come from the
// polynomial alone; returns true when an angle exceeded its range (odd data), and the caller
// then recomputes the ring with the libm branch. A function of its own for `__restrict` (which
// GCC honours on parameters): a gathered load might otherwise alias a store, and the loop stayed
// scalar; with it the loop is vectorized.
// In float, eight samples a vector (double took four, and twice the bytes per gathered range).
// Float keeps the turning angle to ~1e-6 rad: the incoming chord's x component, rho_k -
// rho_kp cos(a), loses ~1 ulp of the range (1e-6 m at 10 m) against a chord of >= 0.25 m, and
// the angle already goes through fastAtan2 in float (~1e-5 rad); the products cross / dot of
// chords of ~0.25 m keep float's relative precision (no sums of large terms here).
template <class SinCos>
inline bool chordKernel(int K, float c, const int* H, const int* L, const int* R, const float* __restrict az,
                        const float* __restrict rho, float* __restrict cross, float* __restrict dot,
                        float* __restrict v2, float* __restrict u2, SinCos sinCos)
{
  int large = 0;  // an int and `|`: no short-circuit branch in the loop
  for (int k = 0; k < K; ++k)
  {
    const int kp = k - std::min(H[k], L[k]), kn = k + std::min(H[k], R[k]);
    large |= chordSample(c, az[k], rho[k], az[kp], rho[kp], az[kn], rho[kn], sinCos, cross[k], dot[k], v2[k], u2[k]);
  }
  return large != 0;
}
RC_SIMD_CLONES_WIDE bool chordProducts(int K, float c, const int* H, const int* L, const int* R,
                                       const float* __restrict az, const float* __restrict rho,
                                       float* __restrict cross, float* __restrict dot, float* __restrict v2,
                                       float* __restrict u2)
{
  return chordKernel(K, c, H, L, R, az, rho, cross, dot, v2, u2, polySinCos<float>);
}
// The chord ends are gathered and used a chunk of samples at a time, so that they stay in L1.
constexpr int kEndsChunk = 256;

#if defined(RC_SIMD_CLONES_ON)
RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// The chord ends' azimuths and ranges of samples [0, K16) (K16 a multiple of 16), gathered into
// ap, rp (k - min(H, L)) and an, rn (k + min(H, R)) with every reach at most 16 samples: then
// the ends of sixteen samples from k0 lie in [k0 - 16, k0 + 32), three vectors of the padded
// arrays, and each gather is one two-source permute of two of them. The compiler's vector form
// of the same reads (chordProducts' clones) builds each gathered lane from a scalar load and an
// insert (no gather instruction: objdump), 64 a group of sixteen. `az` and `rho` must be
// readable on [-16, K16 + 16).
__attribute__((target("avx512f"))) void chordEndsAvx512(int K16, const int* __restrict H, const int* __restrict L,
                                                        const int* __restrict R, const float* __restrict az,
                                                        const float* __restrict rho, float* __restrict ap,
                                                        float* __restrict rp, float* __restrict an,
                                                        float* __restrict rn)
{
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i sixteen = _mm512_set1_epi32(16);
  for (int k0 = 0; k0 < K16; k0 += 16)
  {
    const __m512i h = _mm512_loadu_si512(H + k0);
    const __m512i back = _mm512_min_epi32(h, _mm512_loadu_si512(L + k0));
    const __m512i ahead = _mm512_min_epi32(h, _mm512_loadu_si512(R + k0));
    // lane j's ends: k0 + j - back in [k0 - 16, k0 + 16), index 16 + j - back of (lo, mid);
    // k0 + j + ahead in [k0, k0 + 32), index j + ahead of (mid, hi)
    const __m512i ip = _mm512_sub_epi32(_mm512_add_epi32(iota, sixteen), back);
    const __m512i in = _mm512_add_epi32(iota, ahead);
    const __m512 az_lo = _mm512_loadu_ps(az + k0 - 16), az_mid = _mm512_loadu_ps(az + k0),
                 az_hi = _mm512_loadu_ps(az + k0 + 16);
    const __m512 r_lo = _mm512_loadu_ps(rho + k0 - 16), r_mid = _mm512_loadu_ps(rho + k0),
                 r_hi = _mm512_loadu_ps(rho + k0 + 16);
    _mm512_storeu_ps(ap + k0, _mm512_permutex2var_ps(az_lo, ip, az_mid));
    _mm512_storeu_ps(rp + k0, _mm512_permutex2var_ps(r_lo, ip, r_mid));
    _mm512_storeu_ps(an + k0, _mm512_permutex2var_ps(az_mid, in, az_hi));
    _mm512_storeu_ps(rn + k0, _mm512_permutex2var_ps(r_mid, in, r_hi));
  }
}
RC_AVX512_END

// Lanes of the window (a, b) at indices i in [0, 16): a's lane i where i < 8 (from_b clear), else
// b's lane i - 8 (the permutes read the index's low three bits).
__attribute__((target("avx2"))) inline __m256 pickWindow(__m256 a, __m256 b, __m256i i, __m256 from_b)
{
  return _mm256_blendv_ps(_mm256_permutevar8x32_ps(a, i), _mm256_permutevar8x32_ps(b, i), from_b);
}

// chordEndsAvx512 for CPUs with AVX2 alone, eight samples a step and reaches of at most 8 (the
// default longest chord is 6): the ends of eight samples from k0 lie in [k0 - 8, k0 + 16), and
// each gather is two one-source permutes and a blend (AVX2 has no two-source permute). `az`
// and `rho` must be readable on [-8, K8 + 8).
__attribute__((target("avx2"))) void chordEndsAvx2(int K8, const int* __restrict H, const int* __restrict L,
                                                   const int* __restrict R, const float* __restrict az,
                                                   const float* __restrict rho, float* __restrict ap,
                                                   float* __restrict rp, float* __restrict an, float* __restrict rn)
{
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i eight = _mm256_set1_epi32(8), seven = _mm256_set1_epi32(7);
  for (int k0 = 0; k0 < K8; k0 += 8)
  {
    const __m256i h = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(H + k0));
    const __m256i back = _mm256_min_epi32(h, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(L + k0)));
    const __m256i ahead = _mm256_min_epi32(h, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(R + k0)));
    // lane j's ends: index 8 + j - back of (lo, mid) and j + ahead of (mid, hi)
    const __m256i ip = _mm256_sub_epi32(_mm256_add_epi32(iota, eight), back);
    const __m256i in = _mm256_add_epi32(iota, ahead);
    const __m256 p_hi = _mm256_castsi256_ps(_mm256_cmpgt_epi32(ip, seven));
    const __m256 n_hi = _mm256_castsi256_ps(_mm256_cmpgt_epi32(in, seven));
    const __m256 az_lo = _mm256_loadu_ps(az + k0 - 8), az_mid = _mm256_loadu_ps(az + k0),
                 az_hi = _mm256_loadu_ps(az + k0 + 8);
    const __m256 r_lo = _mm256_loadu_ps(rho + k0 - 8), r_mid = _mm256_loadu_ps(rho + k0),
                 r_hi = _mm256_loadu_ps(rho + k0 + 8);
    _mm256_storeu_ps(ap + k0, pickWindow(az_lo, az_mid, ip, p_hi));
    _mm256_storeu_ps(rp + k0, pickWindow(r_lo, r_mid, ip, p_hi));
    _mm256_storeu_ps(an + k0, pickWindow(az_mid, az_hi, in, n_hi));
    _mm256_storeu_ps(rn + k0, pickWindow(r_mid, r_hi, in, n_hi));
  }
}

// chordKernel on gathered ends (chordEndsAvx512, chordEndsAvx2), with the polynomial: unit-stride
// loads only. (Cloned: the AVX-512 CPUs that gather by chordEndsAvx512 run its AVX-512 form, the
// others, which gather by chordEndsAvx2, its AVX2 form.)
RC_SIMD_CLONES_WIDE bool chordProductsOfEnds(int K, float c, const float* __restrict az, const float* __restrict rho,
                                             const float* __restrict ap, const float* __restrict rp,
                                             const float* __restrict an, const float* __restrict rn,
                                             float* __restrict cross, float* __restrict dot, float* __restrict v2,
                                             float* __restrict u2)
{
  int large = 0;
  for (int k = 0; k < K; ++k)
    large |= chordSample(c, az[k], rho[k], ap[k], rp[k], an[k], rn[k], polySinCos<float>, cross[k], dot[k], v2[k],
                         u2[k]);
  return large != 0;
}
#endif

// The same with the libm branch, for a ring where chordProducts met a large angle.
void chordProductsLibm(int K, float c, const int* H, const int* L, const int* R, const float* __restrict az,
                       const float* __restrict rho, float* __restrict cross, float* __restrict dot,
                       float* __restrict v2, float* __restrict u2)
{
  chordKernel(K, c, H, L, R, az, rho, cross, dot, v2, u2, smallSinCos<float>);
}

// Chord mode: samples per half chord, for a chord of `chord` metres at each range (sample
// spacing ~ rho cos(phi) dtheta), between 1 and max_h. The ceil is by
// truncation (exact: the quotient lies in (0, 2.5e5]), which vectorizes, where SSE2 has no
// rounding instruction and std::ceil stayed a call per sample. In float with the chords
// (eight lanes; the quotient is below 2^24, so the truncation stays exact).
RC_SIMD_CLONES_WIDE void chordSamples(int K, const float* __restrict rho, float cos_phi, float dtheta, float chord,
                                      int max_h, int* __restrict H)
{
  for (int k = 0; k < K; ++k)
  {
    const float spacing = rho[k] * cos_phi * dtheta;
    const float q = chord / (spacing > 1e-6f ? spacing : 1e-6f);  // NaN-safe
    const int t = static_cast<int>(q);
    H[k] = std::clamp(t + (static_cast<float>(t) < q ? 1 : 0), 1, max_h);
  }
}

// Jump mode: link (k-1, k) of each sample k, on the padded ranges `rp`: how badly each side's
// linear extrapolation predicts the other side's range, the smaller of the two, relative to
// range; NaN where k has no link back (L[k] = 0). Branch-free: both predictions are formed and
// the run lengths choose, and every link's quotient is formed, then kept or not, so that the
// loop vectorizes (its divisions were 7 % of the feature stage one at a time).
// In float (eight lanes): a prediction error of ~1 ulp of the range (1e-6 m at 10 m) is 1e-7
// of the range, far below the smallest jump called one (jump_min_ratio, 0.03).
RC_SIMD_CLONES_WIDE void linkJumps(int K, const int* __restrict L, const int* __restrict R, const float* __restrict rp,
                                   float* __restrict jump)
{
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < K; ++k)
  {
    const float r1 = rp[k], r0 = rp[k - 1], rm = rp[k - 2], r2 = rp[k + 1];
    const float e_flat = std::fabs(r1 - r0);
    const float e_left = L[k] >= 2 ? std::fabs(r1 - (2.0f * r0 - rm)) : e_flat;
    const float e_right = R[k] >= 1 ? std::fabs(r0 - (2.0f * r1 - r2)) : e_flat;
    const float j = std::min(e_left, e_right) / std::min(r0, r1);
    jump[k] = L[k] >= 1 ? j : kNaNf;
  }
}

// Discontinuity of each sample: the larger of its two links' jumps (jump[k] is link (k-1, k),
// NaN where there is none; jump[K] repeats jump[0] for the seam). NaN only when both are.
RC_SIMD_CLONES_WIDE void largerLink(int K, const int* __restrict R, const float* __restrict jump,
                                    float* __restrict disc)
{
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < K; ++k)
  {
    const float d = jump[k];
    const float next = jump[k + 1];  // loaded unconditionally (jump has K + 1 entries): no branch
    const float dn = R[k] >= 1 ? next : kNaNf;
    const float larger = d < dn ? dn : d;  // std::max(d, dn), as values (it returns a reference)
    disc[k] = d != d ? dn : larger;        // d is NaN: the other link alone
  }
}

// Run lengths of the samples of segment [p, q) of a ring (see computeRing), those in [0, K).
inline void segmentRuns(int p, int q, int K, int cap, int* __restrict L, int* __restrict R)
{
  const int k0 = std::max(p, 0), k1 = std::min(q, K);
  for (int k = k0; k < k1; ++k)
  {
    L[k] = std::min(k - p, cap);
    R[k] = std::min(q - 1 - k, cap);
  }
}

// Turning angle and curvature of a sample, NaN where undefined. Straight-line (the quotient
// is formed everywhere and then chosen; callers pass `&` rather than `&&`): loops vectorize.
// T is float in chord mode, double in the others.
template <class T>
inline void storeCurvature(T turn, T len, bool defined, float& turning, float& curvature)
{
  const float kappa = static_cast<float>(turn / len);
  turning = defined ? static_cast<float>(turn) : kNaN;
  curvature = (defined & (len > 0)) ? kappa : kNaN;
}

// Per-ring view with circular neighbour access limited to the current run.
struct RingCtx
{
  const ScanGrid& g;
  std::uint32_t b, K;
  bool closed;
  // positions
  std::uint32_t pos(std::int64_t k) const
  {
    return b + static_cast<std::uint32_t>(wrapRingIndex(k, static_cast<std::int64_t>(K)));
  }
};
}  // namespace

const char* coreLoopsIsa()
{
  // the ISA of the loops, then the tuning profile (cpu_tuning.hpp)
  static const std::string s = [] {
#if defined(RC_SIMD_CLONES_ON)
    std::string isa = "baseline";
    if (detail::avx512Forms())
      isa = std::string("avx2, avx512f (features, input, fold, ring sort, vertical, run cut") +
            (verticalPairsRuns() ? "; with BW, DQ, VL the vertical unions)" : ")");
    else if (__builtin_cpu_supports("avx512f"))  // (RC_CPU_AVX512=off: the loader's clones only)
      isa = "avx2, avx512f (features)";
    else if (__builtin_cpu_supports("avx2"))
      isa = "avx2";
#else
    std::string isa = "baseline";
#endif
    return isa + "; tuning " + detail::cpuTuningName() + detail::avx512Note();
  }();
  return s.c_str();
}

void FeatureComputer::compute(const ScanGrid& grid, const Params& params, Features& out)
{
  // No NaN fill of the whole arrays first: computeRing writes every position of its ring (four
  // passes over the frame saved).
  const std::size_t m = grid.size();
  out.curvature.resize(m);
  out.turning.resize(m);
  out.smoothness.resize(m);
  out.discontinuity.resize(m);
  for (int n = 0; n < grid.num_rings; ++n) computeRing(grid, params, n, out);
}

RC_SIMD_CLONES_WIDE void FeatureComputer::computeRing(const ScanGrid& g, const Params& P, int n, Features& out)
{
  const std::uint32_t b = g.ring_begin[static_cast<std::size_t>(n)];
  const std::uint32_t K = g.ring_begin[static_cast<std::size_t>(n) + 1] - b;
  if (K < 2)
  {
    for (auto* v : {&out.curvature, &out.turning, &out.smoothness, &out.discontinuity})
      std::fill(v->begin() + b, v->begin() + b + K, kNaN);
    return;
  }
  const bool closed = g.ring_closed[static_cast<std::size_t>(n)] != 0;
  const double c = P.curvature_mode == CurvatureMode::Paper ? 1.0 : g.ring_cos[static_cast<std::size_t>(n)];
  const double cone_cos = g.ring_cos[static_cast<std::size_t>(n)];
  const RingCtx R{g, b, K, closed};

  // Run lengths: how many links are available to the left / right of each sample (capped).
  // left[k] = number of consecutive predecessors reachable without crossing a gap.
  const int cap = std::max({P.max_chord_samples, P.smoothness_window, 2}) + 1;
  auto& left = runs_;
  growTo(left, 2 * static_cast<std::size_t>(K));
  int* L = left.data();
  int* Rr = left.data() + K;
  const double* rho = g.range.data() + b;
  const std::uint8_t* const lk = g.linked.data() + b;
  // The ring as segments between gaps: seg[i] is the first sample of segment i (a sample k with
  // linked[k] = 0, or a virtual start before the seam), seg[i + 1] its end (exclusive). In
  // segment [p, q): L[k] = min(k - p, cap) and R[k] = min(q - 1 - k, cap). A closed ring's runs
  // continue across the seam: its first segment starts `run` links before the ring's first
  // sample, and its last ends `run` links after its last one, found by a walk of at most `cap`
  // links each. (An open ring has linked[first] = 0, so its runs start at 0, and it ends at K.)
  // Gaps are found by memchr (zero bytes, many at a time) and each segment's runs written by a
  // loop that vectorizes: two scalar passes carrying the last gap cost ~23 instructions a sample
  // (callgrind), and the smoothness below visits only the samples near a gap from the same list.
  growTo(seg_, static_cast<std::size_t>(K) + 2);
  int* const seg = seg_.data();
  int num_seg = 0;
  {
    int run = 0;
    if (closed)
      for (std::uint32_t j = K; j-- > 0 && lk[j] != 0 && run < cap;) ++run;
    seg[num_seg++] = -run - 1;
    for (const std::uint8_t* z = lk;
         (z = static_cast<const std::uint8_t*>(std::memchr(z, 0, static_cast<std::size_t>(lk + K - z)))) != nullptr; ++z)
      seg[num_seg++] = static_cast<int>(z - lk);
    run = 0;
    if (closed)
      for (std::uint32_t j = 1; j <= K && lk[j == K ? 0 : j] != 0 && run < cap; ++j) ++run;
    seg[num_seg++] = closed && lk[0] != 0 ? static_cast<int>(K) + run + 1 : static_cast<int>(K);
    for (int i = 0; i + 1 < num_seg; ++i) segmentRuns(seg[i], seg[i + 1], static_cast<int>(K), cap, L, Rr);
  }

  // The ring's azimuths, and its ranges in float, with `cap` samples of padding on each side: the
  // neighbours of a closed ring across the seam, copies of the end samples for an open one (never
  // used: the run lengths keep every reach inside the ring). Neighbour k + j is then azp[k + j],
  // with no wrap-around arithmetic per access. The double ranges are read in place (`rho`): the
  // smoothness's windows wrap across the seam themselves (a padded double copy of every ring cost
  // a memcpy of 8 bytes a sample, and the float conversion read that copy).
  // The default modes' features (Chord, Jump, Detrended with small windows) run in float, eight
  // samples a vector, on the float ranges; the other modes keep the double ranges, and so do the
  // smoothness's prefix sums (squared ranges summed over a ring).
  // (16 more on each side, and 16 spare: the windows chordEndsAvx512 reads past the padding,
  // values never used)
  growTo(az_pad_, K + 2 * static_cast<std::size_t>(cap) + 48);
  growTo(rho_pad_f_, K + 2 * static_cast<std::size_t>(cap) + 48);
  float* const azp = az_pad_.data() + cap + 16;
  float* const rpf = rho_pad_f_.data() + cap + 16;
  std::copy(g.azimuth.begin() + b, g.azimuth.begin() + b + K, azp);
  for (std::uint32_t k = 0; k < K; ++k) rpf[k] = static_cast<float>(rho[k]);
  const auto padFrom = [&](std::int64_t k) {
    return closed ? R.pos(k) : b + static_cast<std::uint32_t>(std::clamp<std::int64_t>(k, 0, K - 1));
  };
  for (std::int64_t j = 1; j <= cap; ++j)
  {
    const std::int64_t lo = -j, hi = static_cast<std::int64_t>(K) - 1 + j;
    rpf[lo] = static_cast<float>(g.range[padFrom(lo)]);
    azp[lo] = g.azimuth[padFrom(lo)];
    rpf[hi] = static_cast<float>(g.range[padFrom(hi)]);
    azp[hi] = g.azimuth[padFrom(hi)];
  }
  const bool chord_mode = P.curvature_mode == CurvatureMode::Chord;
  const bool jump_mode = P.discontinuity_mode == DiscontinuityMode::Jump;

  // Local development of a neighbour j around vertex k: coordinates of w_j with w_k = (rho_k, 0).
  const bool exact = !chord_mode;
  auto relAngle = [&](std::uint32_t pk, std::uint32_t pj) -> double {
    if (!exact) return wrapPi(static_cast<double>(g.azimuth[pj]) - g.azimuth[pk]);
    const double xk = g.x[pk], yk = g.y[pk], xj = g.x[pj], yj = g.y[pj];
    return std::atan2(xk * yj - yk * xj, xk * xj + yk * yj);
  };
  auto develop = [&](std::uint32_t pk, std::uint32_t pj, double& wx, double& wy) {
    double s, co;
    smallSinCos(c * relAngle(pk, pj), s, co);
    wx = g.range[pj] * co;
    wy = g.range[pj] * s;
  };

  // Curvature in short loops of independent iterations (the chord's sample count, the developed
  // chords, the turning angle and arc length, kappa = turn / len) rather than one long chain of
  // dependent divisions and square roots per sample: the CPU overlaps their divisions, and in
  // chord mode each loop vectorizes.
  float* const turning = out.turning.data() + b;
  float* const curvature = out.curvature.data() + b;
  if (chord_mode)
  {
    // Chord mode (see chordProducts), in float. If an angle exceeded the polynomial's range, the
    // ring is recomputed with the libm branch (rare; only odd data).
    const float res = std::max(1e-6f, g.azimuth_resolution);
    const float cf = g.ring_cos[static_cast<std::size_t>(n)];
    growTo(half_, K);
    growTo(chord_, 4 * static_cast<std::size_t>(K) + 4 * kEndsChunk);
    int* H = half_.data();
    float* CROSS = chord_.data();  // the chords' cross and dot products, squared lengths
    float* DOT = CROSS + K;
    float* V2 = DOT + K;
    float* U2 = V2 + K;
    chordSamples(static_cast<int>(K), rpf, cf, res, P.chord_length, P.max_chord_samples, H);
    const int Ki = static_cast<int>(K);
    // Vectorized: fastAtan2 is branch-free, and std::sqrt has no errno branch (-fno-math-errno).
    // The turning angle and arc length go straight into kappa (one loop, not two through arrays).
    const auto curvatureOf = [CROSS, DOT, V2, U2, L, Rr, turning, curvature](std::uint32_t k0, std::uint32_t k1)
                                 __attribute__((always_inline)) {
      for (std::uint32_t k = k0; k < k1; ++k)
      {
        const float turn = std::fabs(fastAtan2(CROSS[k], DOT[k]));
        const float len = 0.5f * (std::sqrt(V2[k]) + std::sqrt(U2[k]));
        storeCurvature(turn, len, (L[k] != 0) & (Rr[k] != 0), turning[k], curvature[k]);
      }
    };
    std::uint32_t curved = 0;  // samples [0, curved) have their curvature stored
    bool large = false;
#if defined(RC_SIMD_CLONES_ON)
    // Where every reach is at most 16 samples (H <= max_chord_samples) on AVX-512, or 8 on AVX2,
    // the ends come from permutes (chordEndsAvx512, chordEndsAvx2) into a chunk's arrays, and the
    // chunk's products and curvatures follow while they are in L1 (the ends of a whole ring
    // first, then its products: features 1.09 of this on KITTI frames, 1.07 on the 29k ones).
    // The last K % width samples take the compiler's form.
    // (always_inline: the clone of computeRing it runs in holds the loops' vector code; outlined,
    // GCC compiled it once, for the baseline, and the features took 2.3 times as long)
    const auto byChunks = [&](int width, auto ends) __attribute__((always_inline)) {
      float* const AP = U2 + K;  // the chunk's chord ends: azimuths and ranges
      float* const RP = AP + kEndsChunk;
      float* const AN = RP + kEndsChunk;
      float* const RN = AN + kEndsChunk;
      const int Kw = Ki / width * width;
      for (int k0 = 0; k0 < Kw; k0 += kEndsChunk)
      {
        const int len = std::min(kEndsChunk, Kw - k0);
        ends(len, H + k0, L + k0, Rr + k0, azp + k0, rpf + k0, AP, RP, AN, RN);
        const bool chunk = chordProductsOfEnds(len, cf, azp + k0, rpf + k0, AP, RP, AN, RN, CROSS + k0, DOT + k0,
                                               V2 + k0, U2 + k0);
        large = large || chunk;
        curvatureOf(static_cast<std::uint32_t>(k0), static_cast<std::uint32_t>(k0 + len));
      }
      curved = static_cast<std::uint32_t>(Kw);
      const bool tail = chordProducts(Ki - Kw, cf, H + Kw, L + Kw, Rr + Kw, azp + Kw, rpf + Kw, CROSS + Kw,
                                      DOT + Kw, V2 + Kw, U2 + Kw);
      large = large || tail;
    };
    if (P.max_chord_samples <= 16 && detail::avx512Forms())
      byChunks(16, chordEndsAvx512);
    else if (P.max_chord_samples <= 8 && __builtin_cpu_supports("avx2"))
      byChunks(8, chordEndsAvx2);
    else
#endif
    {
      large = chordProducts(Ki, cf, H, L, Rr, azp, rpf, CROSS, DOT, V2, U2);
    }
    if (large)
    {
      chordProductsLibm(Ki, cf, H, L, Rr, azp, rpf, CROSS, DOT, V2, U2);
      curved = 0;
    }
    curvatureOf(curved, K);
  }
  else
  {
    growTo(turn_len_, 2 * static_cast<std::size_t>(K));
    double* TURN = turn_len_.data();
    double* LEN = TURN + K;
    for (std::uint32_t k = 0; k < K; ++k)
    {
      if (L[k] == 0 || Rr[k] == 0) continue;  // turning angle needs a neighbour on each side
      const std::uint32_t pk = b + k;
      const std::uint32_t pp = R.pos(static_cast<std::int64_t>(k) - 1);
      const std::uint32_t pn = R.pos(static_cast<std::int64_t>(k) + 1);
      double ax, ay, cx, cy;
      develop(pk, pp, ax, ay);
      develop(pk, pn, cx, cy);
      const double vx = rho[k] - ax, vy = -ay;  // incoming chord
      const double ux = cx - rho[k], uy = cy;   // outgoing chord
      const double cross = vx * uy - vy * ux, dot = vx * ux + vy * uy;
      TURN[k] = std::fabs(std::atan2(cross, dot));
      // Eq 6: cone-metric arc length of the incoming step (midpoint rule); Eq 9 divides by it.
      const double dr = rho[k] - g.range[pp];
      const double rbar = 0.5 * (rho[k] + g.range[pp]);
      const double dth = relAngle(pp, pk);
      LEN[k] = std::sqrt(dr * dr + (rbar * cone_cos * dth) * (rbar * cone_cos * dth));
    }
    for (std::uint32_t k = 0; k < K; ++k)
      storeCurvature(TURN[k], LEN[k], (L[k] != 0) & (Rr[k] != 0), turning[k], curvature[k]);
  }

  // Discontinuity.
  if (!jump_mode)
  {
    for (std::uint32_t k = 0; k < K; ++k)
    {
      if (L[k] == 0)
      {
        out.discontinuity[b + k] = kNaN;
        continue;
      }
      const std::uint32_t pk = b + k, pp = R.pos(static_cast<std::int64_t>(k) - 1);
      const double dr = rho[k] - g.range[pp];
      const double rbar = 0.5 * (rho[k] + g.range[pp]);
      const double dth = relAngle(pp, pk);
      const double ds = std::sqrt(dr * dr + (rbar * cone_cos * dth) * (rbar * cone_cos * dth));
      out.discontinuity[pk] = ds > 0 ? static_cast<float>(std::fabs(dr) / ds) : 0.0f;
    }
  }
  else
  {
    // Link (k-1, k): how badly each side's linear extrapolation predicts the other side's range,
    // the smaller of the two, relative to range. A grazing plane is predicted well from both
    // sides; a depth jump from neither. A point takes the larger of its two links.
    // Each link once (a point shares its links with its neighbours): jump[k] is link (k-1, k),
    // NaN where there is none, and jump[K] repeats jump[0] (the seam's link of a closed ring), so
    // that largerLink reads both links of every sample without a wrap.
    auto& jump = jump_;
    growTo(jump, K + 1);
    linkJumps(static_cast<int>(K), L, Rr, rpf, jump.data());
    jump[K] = jump[0];
    largerLink(static_cast<int>(K), Rr, jump.data(), out.discontinuity.data() + b);
  }

  // Smoothness over a window of +-w samples (smoothness.cpp).
  growTo(prefix_, smoothnessScratch(static_cast<int>(K), P.smoothness_window, closed));
  ringSmoothness(static_cast<int>(K), P.smoothness_window, closed, P.smoothness_mode == SmoothnessMode::Detrended, rho,
                 rpf, L, Rr, seg, num_seg, prefix_.data(), out.smoothness.data() + b);
}

}  // namespace ring_curvature
