// The vertical unions' AVX-512 form (see vertical_pairs.hpp).
//
// The AVX2 loop (primitives.cpp) takes one position at a time and branches on each test: all
// three candidates out of range, the label, the azimuth, the end of the stretch it skips. Those
// outcomes are data (walls and ground alternate along a ring), and mispredicted branches were the
// likely cost: the loop took 12 % of the benchmark's samples on KITTI and OS1-128 frames, and
// testing its idle stretches alone eight at a time gained nothing (docs/benchmark_history.md). Here every
// position is tested, without a branch: eight positions a vector, their candidates above taken
// by permutes from a window of sixteen samples (the nearest sample above moves along the ring
// with the position), and only where the pair of runs changes is an entry written for the
// union-find. The positions the loop skipped (their candidates all lie in the run just joined)
// can only give the pair of the position before them: no entry.
#include "vertical_pairs.hpp"

#include "angles.hpp"
#include "proximity.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

namespace ring_curvature
{

#if defined(RC_SIMD_CLONES_ON)
namespace
{
// One position's run above, or `none`, with joinAbove's tests in its order (primitives.cpp):
// for the blocks whose candidates leave the window (the seam, gaps above).
std::uint32_t runAbove(const VerticalRing& V, std::uint32_t p, Label l, std::uint32_t none)
{
  if (V.up[p] < 0) return none;
  const auto uu = static_cast<std::uint32_t>(V.up[p]);
  const std::uint32_t c1 = uu > V.b ? uu - 1 : V.e - 1, c2 = uu + 1 < V.e ? uu + 1 : V.b;
  const double ra = V.range[p];
  const float aa = V.azimuth[p];
  const auto takes = [&V, ra, aa, l](std::uint32_t q, bool check_azimuth) {
    return inRangeHalf(ra, V.range[q], V.half_ratio, V.range_min) && V.lab[q] == l &&
           (!check_azimuth || angDiff(aa, V.azimuth[q]) <= V.az_tol);  // Eq 19-20
  };
  if (takes(uu, !V.organized)) return V.run[uu];
  if (takes(c1, true)) return V.run[c1];
  if (takes(c2, true)) return V.run[c2];
  return none;
}

inline std::uint64_t pairOf(std::uint32_t rp, std::uint32_t rq) { return rp | static_cast<std::uint64_t>(rq) << 32; }

#define RC_VERTICAL_TARGET target("avx512f,avx512dq,avx512bw,avx512vl,avx2,popcnt")

// A block's window above (sixteen places from its base) and its eight positions' own values.
// The 32-bit values in eight lanes (256 bits, AVX-512VL), so that every test yields the eight
// bits of the doubles' masks: sixteen-lane masks next to eight-lane ones went through general
// registers to be widened.
struct Window
{
  __m512d r_lo, r_hi;  // ranges: places 0-7, 8-15
  __m512 az;
  __m512i lab;
  __m512d ra;  // the positions'
  __m256 aa;
  __m256i la;
  __m512d half, range_min;
  __m256 pi, two_pi, az_tol;
};

RC_AVX512_BEGIN
// entries idx (eight lanes) of a table of sixteen
__attribute__((RC_VERTICAL_TARGET, always_inline)) inline __m256i take(__m256i idx, __m512i table)
{
  return _mm512_castsi512_si256(_mm512_permutexvar_epi32(_mm512_castsi256_si512(idx), table));
}
__attribute__((RC_VERTICAL_TARGET, always_inline)) inline __m256 take(__m256i idx, __m512 table)
{
  return _mm512_castps512_ps256(_mm512_permutexvar_ps(_mm512_castsi256_si512(idx), table));
}

// runAbove's tests of the candidates at window places idx, lane by lane in the same operations
// (fabs as a cleared sign bit, t < min ? min : t as max(min, t))
__attribute__((RC_VERTICAL_TARGET, always_inline)) inline __mmask8 joins(const Window& w, __m256i idx,
                                                                         bool check_azimuth)
{
  const __m512i abs64 = _mm512_set1_epi64(0x7fffffffffffffffLL);
  const __m256i abs32 = _mm256_set1_epi32(0x7fffffff);
  const __m512d rb = _mm512_permutex2var_pd(w.r_lo, _mm512_cvtepu32_epi64(idx), w.r_hi);
  const __m512d t = _mm512_mul_pd(w.half, _mm512_add_pd(w.ra, rb));
  const __m512d tol = _mm512_max_pd(w.range_min, t);
  const __m512d dist = _mm512_castsi512_pd(_mm512_and_epi64(_mm512_castpd_si512(_mm512_sub_pd(w.ra, rb)), abs64));
  __mmask8 ok = _mm512_cmp_pd_mask(dist, tol, _CMP_NGT_UQ);
  ok = _mm256_mask_cmpeq_epi32_mask(ok, take(idx, w.lab), w.la);
  if (check_azimuth)
  {
    const __m256 d = _mm256_sub_ps(w.aa, take(idx, w.az));
    const __m256 a = _mm256_castsi256_ps(_mm256_and_si256(_mm256_castps_si256(d), abs32));
    const __m256 c = _mm256_mask_sub_ps(a, _mm256_cmp_ps_mask(a, w.pi, _CMP_GT_OQ), w.two_pi, a);
    ok = _mm256_mask_cmp_ps_mask(ok, c, w.az_tol, _CMP_LE_OQ);  // Eq 19
  }
  return ok;
}
RC_AVX512_END
}  // namespace

RC_AVX512_BEGIN
__attribute__((RC_VERTICAL_TARGET)) std::size_t verticalPairsAvx512(const VerticalRing& V, std::uint32_t b0,
                                                                   std::uint32_t e0, std::uint32_t none,
                                                                   std::uint64_t* pairs)
{
  const std::uint32_t b = V.b, e = V.e;
  const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1), sixteen = _mm256_set1_epi32(16);
  const __m256i vb = _mm256_set1_epi32(static_cast<int>(b)), ve = _mm256_set1_epi32(static_cast<int>(e));
  const __m256i ve1 = _mm256_set1_epi32(static_cast<int>(e - 1)), vnone = _mm256_set1_epi32(static_cast<int>(none));
  const __m512i no_pair = _mm512_set1_epi64(static_cast<long long>(kNoVerticalPair));
  const __m512d half = _mm512_set1_pd(V.half_ratio), range_min = _mm512_set1_pd(V.range_min);
  const __m256 pi = _mm256_set1_ps(kPi), two_pi = _mm256_set1_ps(kTwoPi), az_tol = _mm256_set1_ps(V.az_tol);
  // (locals: through V, the loop reloaded every pointer after each store to pairs)
  const Label* const lab = V.lab;
  const std::int32_t* const above = V.up;
  const std::uint32_t* const run = V.run;
  const double* const range = V.range;
  const float* const azimuth = V.azimuth;
  const bool organized = V.organized;
  std::uint64_t prev = kNoVerticalPair;
  std::size_t np = 0;
  for (std::uint32_t p = b0; p < e0; p += 8)
  {
    const std::uint32_t left = e0 - p;
    const auto lanes = static_cast<__mmask8>(left >= 8 ? 0xFFu : (1u << left) - 1);
    const __m256i up = _mm256_maskz_loadu_epi32(lanes, above + p);
    const __m256i rp = _mm256_maskz_loadu_epi32(lanes, run + p);
    // a wanted label (a run) and a sample above
    const __mmask8 act = _mm256_mask_cmpneq_epi32_mask(_mm256_mask_cmpge_epi32_mask(lanes, up, zero), rp, vnone);
    if (act == 0)
    {
      prev = kNoVerticalPair;
      continue;
    }
    const __m256i u1 = _mm256_add_epi32(up, one);
    const __m256i c1 = _mm256_mask_blend_epi32(_mm256_cmpgt_epu32_mask(up, vb), ve1, _mm256_sub_epi32(up, one));
    const __m256i c2 = _mm256_mask_blend_epi32(_mm256_cmplt_epu32_mask(u1, ve), vb, u1);
    // the window from the first position's candidate before: the samples above move along
    // with the positions (where they do not, the test below sends the block to runAbove)
    const auto first = static_cast<std::uint32_t>(above[p + static_cast<std::uint32_t>(__builtin_ctz(act))]);
    const std::uint32_t base = first > b ? first - 1 : b;
    const __m256i vbase = _mm256_set1_epi32(static_cast<int>(base));
    const __m256i i0 = _mm256_sub_epi32(up, vbase), i1 = _mm256_sub_epi32(c1, vbase), i2 = _mm256_sub_epi32(c2, vbase);
    const __mmask8 in_window = _mm256_mask_cmplt_epu32_mask(
        _mm256_mask_cmplt_epu32_mask(_mm256_cmplt_epu32_mask(i0, sixteen), i1, sixteen), i2, sixteen);
    if ((act & ~in_window) != 0)
    {
      const std::uint32_t n = left >= 8 ? 8 : left;
      for (std::uint32_t i = 0; i < n; ++i)
      {
        const std::uint32_t q = p + i, r = run[q];
        const std::uint32_t rq = r == none ? none : runAbove(V, q, lab[q], none);
        const std::uint64_t pair = rq == none ? kNoVerticalPair : pairOf(r, rq);
        if (pair != kNoVerticalPair && pair != prev) pairs[np++] = pair;
        prev = pair;
      }
      continue;
    }
    // the window above: [base, base + 16) within the ring (the labels are the caller's array:
    // masked loads, nothing read past e0 or e)
    const std::uint32_t wn = e - base;
    const auto wmask = static_cast<__mmask16>(wn >= 16 ? 0xFFFFu : (1u << wn) - 1);
    const __m512d r_lo = _mm512_maskz_loadu_pd(static_cast<__mmask8>(wmask), range + base);
    const __m512d r_hi = _mm512_maskz_loadu_pd(static_cast<__mmask8>(wmask >> 8), range + base + 8);
    const __m512 w_az = _mm512_maskz_loadu_ps(wmask, azimuth + base);
    const __m512i w_run = _mm512_maskz_loadu_epi32(wmask, run + base);
    const __m512i w_lab = _mm512_cvtepu8_epi32(_mm_maskz_loadu_epi8(wmask, lab + base));
    const __m256i la = _mm256_cvtepu8_epi32(_mm_maskz_loadu_epi8(lanes, lab + p));
    const __m512d ra = _mm512_maskz_loadu_pd(lanes, range + p);
    const __m256 aa = _mm256_maskz_loadu_ps(lanes, azimuth + p);
    const Window w{r_lo, r_hi, w_az, w_lab, ra, aa, la, half, range_min, pi, two_pi, az_tol};
    const __mmask8 m0 = joins(w, i0, !organized), m1 = joins(w, i1, true), m2 = joins(w, i2, true);
    const __mmask8 any = act & (m0 | m1 | m2);
    const __m256i sel = _mm256_mask_blend_epi32(m0, _mm256_mask_blend_epi32(m1, i2, i1), i0);
    const __m256i rq = take(sel, w_run);
    const __m512i pair = _mm512_mask_mov_epi64(
        no_pair, any, _mm512_or_si512(_mm512_cvtepu32_epi64(rp), _mm512_slli_epi64(_mm512_cvtepu32_epi64(rq), 32)));
    // each lane against the one before it (lane 0: the last of the block before)
    const __m512i before = _mm512_alignr_epi64(pair, _mm512_set1_epi64(static_cast<long long>(prev)), 7);
    const __mmask8 fresh = _mm512_mask_cmpneq_epi64_mask(any, pair, before);
    // (compressed in a register and stored whole: the compress to memory took the loop's longest
    // stall, 9 % of its samples)
    _mm512_storeu_si512(pairs + np, _mm512_maskz_compress_epi64(fresh, pair));
    np += static_cast<std::size_t>(__builtin_popcount(fresh));
    // (lanes past left hold no pair, as the position after the ring's last would)
    prev = static_cast<std::uint64_t>(_mm_cvtsi128_si64(_mm512_castsi512_si128(_mm512_alignr_epi64(pair, pair, 7))));
  }
  return np;
}
RC_AVX512_END
#undef RC_VERTICAL_TARGET
#endif

}  // namespace ring_curvature
