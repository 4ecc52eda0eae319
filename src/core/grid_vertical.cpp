// The nearest sample on the ring above each grid position (ScanGrid::up): a merge walk along two
// sorted rings and the choice among three candidates for unorganized clouds, the same column one
// row up for organized ones.
#include "ring_curvature/scan_grid.hpp"

#include "angles.hpp"
#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

namespace
{

// The nearest sample above each position p of a ring (b, e), with up[p] the last sample of the
// ring above (ub, ue) at or before p's azimuth (or ub): of up[p], its successor (around the
// seam) and the ring's last one, the nearest azimuth circularly, the first of equals in that
// order. Branch-free: which one wins is a coin toss per point. |wrapPi(d)| for |d| < 2 pi is
// |d| or 2 pi - |d|, the same float operations.
RC_SIMD_CLONES void nearestAbove(std::uint32_t b, std::uint32_t e, std::uint32_t ub, std::uint32_t ue,
                                 const float* __restrict az, std::int32_t* __restrict up)
{
  const float last = az[ue - 1];
  for (std::uint32_t p = b; p < e; ++p)
  {
    const float a = az[p];
    const std::uint32_t q = static_cast<std::uint32_t>(up[p]);
    const std::uint32_t c1 = q + 1 < ue ? q + 1 : ub;
    const float d0 = circularDistance(az[q] - a), d1 = circularDistance(az[c1] - a),
                d2 = circularDistance(last - a);
    std::uint32_t best = d1 < d0 ? c1 : q;
    const float bd = d1 < d0 ? d1 : d0;
    best = d2 < bd ? ue - 1 : best;
    up[p] = static_cast<std::int32_t>(best);
  }
}

// One ring's part of the search: its samples [p, e) left, the ring above (ub, ue), the walk's
// position q, and whether the vector path left its next group to the walk.
struct VerticalStream
{
  std::uint32_t p, e, ub, ue, q;
  bool stuck;
};

// The walk and the choice for the next `count` samples of s.
void verticalWalk(const float* az, std::int32_t* up, VerticalStream& s, std::uint32_t count)
{
  const std::uint32_t done = s.p, stop = std::min(s.e, s.p + count);
  std::uint32_t q = s.q;
  for (std::uint32_t p = done; p < stop; ++p)
  {
    const float a = az[p];
    while (q + 1 < s.ue && az[q + 1] <= a) ++q;
    up[p] = static_cast<std::int32_t>(q);
  }
  nearestAbove(done, stop, s.ub, s.ue, az, up);
  s.p = stop;
  s.q = q;
  s.stuck = false;
}

#if defined(RC_SIMD_CLONES_ON)
// |wrapPi(d)| eight lanes at a time: circularDistance (angles.hpp), `a > pi ? 2 pi - a : a` with
// a = |d|, as min(2 pi - a, a) (vminps returns its second operand unless the first is less).
// The same bits for every a >= 0, NaN included (checked over all of them): 2 pi - a rounds to
// at most pi < a when a > pi, and to at least a when a <= pi (kTwoPi is exactly 2 kPi). Two
// operations instead of a compare and a three-uop blend.
__attribute__((target("avx2"))) inline __m256 circDist8(__m256 d)
{
  const __m256 a = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), d);
  return _mm256_min_ps(_mm256_sub_ps(_mm256_set1_ps(kTwoPi), a), a);
}

// The merge walk and nearestAbove's choice for eight samples of a ring at a time, where the
// walk's exit was a data-dependent branch per sample. With q the walk's position before the
// eight (the last sample above at or before the previous one), each one's stop is q plus how
// many of az[q + 1 .. q + 16] lie at or below its azimuth: the walk stops at the first sample
// above that does not, and those sixteen are sorted, so this is the same count. It holds when
// the count stays below 16 (the stop lies inside the window), the window lies inside the ring
// above (no seam candidate but the last) and no azimuth in it or among the eight is NaN (which
// would stop the walk early); otherwise the group is left to the walk (`stuck`). The three
// candidates' azimuths are picked from the window's registers by the count.
__attribute__((target("avx2"), always_inline)) inline bool verticalGroup(const float* __restrict az,
                                                                         std::int32_t* __restrict up,
                                                                         VerticalStream& s)
{
  const std::uint32_t q = s.q, p = s.p;
  if (p + 8 > s.e || q + 16 >= s.ue)
  {
    s.stuck = p < s.e;
    return false;
  }
  const __m256 a = _mm256_loadu_ps(az + p);
  const float* const w = az + q;
  const __m256 w0 = _mm256_loadu_ps(w), w1 = _mm256_loadu_ps(w + 8);      // az[q + k], k 0..15
  const __m256 s0 = _mm256_loadu_ps(w + 1), s1 = _mm256_loadu_ps(w + 9);  // az[q + k + 1]
  __m256i c[4];
  for (int j = 0; j < 4; ++j)
  {
    __m256i acc = _mm256_castps_si256(_mm256_cmp_ps(_mm256_broadcast_ss(w + 1 + j), a, _CMP_LE_OQ));
    for (int k = 1 + j + 4; k <= 16; k += 4)
    {
      const __m256 le = _mm256_cmp_ps(_mm256_broadcast_ss(w + k), a, _CMP_LE_OQ);
      acc = _mm256_add_epi32(acc, _mm256_castps_si256(le));
    }
    c[j] = acc;
  }
  // the negated count (each true comparison is -1)
  const __m256i neg = _mm256_add_epi32(_mm256_add_epi32(c[0], c[1]), _mm256_add_epi32(c[2], c[3]));
  const __m256i cnt = _mm256_sub_epi32(_mm256_setzero_si256(), neg);
  const __m256 nan = _mm256_or_ps(_mm256_cmp_ps(a, a, _CMP_UNORD_Q), _mm256_cmp_ps(s0, s1, _CMP_UNORD_Q));
  const __m256 bad = _mm256_or_ps(nan, _mm256_castsi256_ps(_mm256_cmpeq_epi32(cnt, _mm256_set1_epi32(16))));
  if (_mm256_movemask_ps(bad) != 0)
  {
    s.stuck = true;
    return false;
  }
  // az[q + cnt] and az[q + cnt + 1]: lanes 0..7 of the first register or (cnt >= 8) the second
  const __m256 hi = _mm256_castsi256_ps(_mm256_slli_epi32(cnt, 28));
  const __m256 aq = _mm256_blendv_ps(_mm256_permutevar8x32_ps(w0, cnt), _mm256_permutevar8x32_ps(w1, cnt), hi);
  const __m256 an = _mm256_blendv_ps(_mm256_permutevar8x32_ps(s0, cnt), _mm256_permutevar8x32_ps(s1, cnt), hi);
  const __m256 d0 = circDist8(_mm256_sub_ps(aq, a)), d1 = circDist8(_mm256_sub_ps(an, a));
  const __m256 d2 = circDist8(_mm256_sub_ps(_mm256_set1_ps(az[s.ue - 1]), a));
  const __m256 m1 = _mm256_cmp_ps(d1, d0, _CMP_LT_OQ);
  const __m256i pos = _mm256_add_epi32(_mm256_set1_epi32(static_cast<std::int32_t>(q)), cnt);
  const __m256i best = _mm256_sub_epi32(pos, _mm256_castps_si256(m1));  // + 1 where the successor is nearer
  const __m256 bd = _mm256_min_ps(d1, d0);                                // d1 < d0 ? d1 : d0
  const __m256 m2 = _mm256_cmp_ps(d2, bd, _CMP_LT_OQ);
  const __m256i last = _mm256_set1_epi32(static_cast<std::int32_t>(s.ue - 1));
  const __m256 chosen = _mm256_blendv_ps(_mm256_castsi256_ps(best), _mm256_castsi256_ps(last), m2);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(up + p), _mm256_castps_si256(chosen));
  s.q = q + static_cast<std::uint32_t>(_mm256_extract_epi32(cnt, 7));
  s.p = p + 8;
  return true;
}

// Groups of two rings in turn until one of them cannot take its next: each group's window
// starts where the one before of its ring stopped, a chain of ~20 cycles that bounded one ring
// alone; two rings' chains interleave.
__attribute__((target("avx2"))) void verticalGroupsAvx2(const float* __restrict az, std::int32_t* __restrict up,
                                                        VerticalStream& s0, VerticalStream& s1)
{
  while (verticalGroup(az, up, s0) & verticalGroup(az, up, s1))
  {
  }
}
__attribute__((target("avx2"))) void verticalGroupsAvx2(const float* __restrict az, std::int32_t* __restrict up,
                                                        VerticalStream& s0)
{
  while (verticalGroup(az, up, s0))
  {
  }
}

RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// circDist8 sixteen lanes at a time: AVX-512F has no float and-not (AVX-512DQ has), so |d| is an
// integer and of the bits; vminps keeps its semantics.
__attribute__((target("avx512f"))) inline __m512 circDist16(__m512 d)
{
  const __m512 a = _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(d), _mm512_set1_epi32(0x7fffffff)));
  return _mm512_min_ps(_mm512_sub_ps(_mm512_set1_ps(kTwoPi), a), a);
}

// verticalGroup for sixteen samples against a window of 32 above, az[q + 1 .. q + 32]: the same
// invariants (the count below 32, the window and the successor inside the ring above, no NaN
// among the sixteen or in the window), with a group that breaks them handed to the eight-lane
// form, which takes it or leaves it to the walk. The counts: a branch-free binary search per
// lane in the sorted window (five two-register permutes and compares instead of 32 compares
// and adds); the next window's start, the chain from group to group, is the last sample's count
// taken apart as the popcount of two compares, so it waits on no search. Both counts are the
// same number as the walk's when the window is sorted and free of NaN. The candidates' azimuths
// are permutes of the window's registers by the count.
__attribute__((target("avx512f"), always_inline)) inline bool verticalGroup16(const float* __restrict az,
                                                                              std::int32_t* __restrict up,
                                                                              VerticalStream& s)
{
  const std::uint32_t q = s.q, p = s.p;
  if (p + 16 > s.e || q + 32 >= s.ue) return verticalGroup(az, up, s);
  const __m512 a = _mm512_loadu_ps(az + p);
  const float* const w = az + q;
  const __m512 n0 = _mm512_loadu_ps(w + 1), n1 = _mm512_loadu_ps(w + 17);  // az[q + 1 + k], k 0..31
  const __m512 end = _mm512_set1_ps(az[p + 15]);
  const unsigned below = _mm512_cmp_ps_mask(n0, end, _CMP_LE_OQ) |
                         (static_cast<unsigned>(_mm512_cmp_ps_mask(n1, end, _CMP_LE_OQ)) << 16);
  const int last = __builtin_popcount(below);
  const __mmask16 nan = _mm512_cmp_ps_mask(a, a, _CMP_UNORD_Q) | _mm512_cmp_ps_mask(n0, n1, _CMP_UNORD_Q);
  if (nan != 0 || last == 32) return verticalGroup(az, up, s);
  // how many of az[q + 1 .. q + 31] lie at or below each azimuth (the 32nd does not: last < 32)
  __m512i cnt = _mm512_setzero_si512();
  for (int step = 16; step > 0; step /= 2)
  {
    const __m512i at = _mm512_add_epi32(cnt, _mm512_set1_epi32(step - 1));
    const __mmask16 le = _mm512_cmp_ps_mask(_mm512_permutex2var_ps(n0, at, n1), a, _CMP_LE_OQ);
    cnt = _mm512_mask_add_epi32(cnt, le, cnt, _mm512_set1_epi32(step));
  }
  const __m512 aq = _mm512_permutex2var_ps(_mm512_loadu_ps(w), cnt, _mm512_loadu_ps(w + 16));  // az[q + cnt]
  const __m512 an = _mm512_permutex2var_ps(n0, cnt, n1);                                      // az[q + cnt + 1]
  const __m512 d0 = circDist16(_mm512_sub_ps(aq, a)), d1 = circDist16(_mm512_sub_ps(an, a));
  const __m512 d2 = circDist16(_mm512_sub_ps(_mm512_set1_ps(az[s.ue - 1]), a));
  const __mmask16 m1 = _mm512_cmp_ps_mask(d1, d0, _CMP_LT_OQ);
  const __m512i pos = _mm512_add_epi32(_mm512_set1_epi32(static_cast<std::int32_t>(q)), cnt);
  const __m512i best = _mm512_mask_add_epi32(pos, m1, pos, _mm512_set1_epi32(1));  // the successor where nearer
  const __mmask16 m2 = _mm512_cmp_ps_mask(d2, _mm512_min_ps(d1, d0), _CMP_LT_OQ);   // min: d1 < d0 ? d1 : d0
  const __m512i top = _mm512_set1_epi32(static_cast<std::int32_t>(s.ue - 1));  // the ring's last sample
  _mm512_storeu_si512(up + p, _mm512_mask_blend_epi32(m2, best, top));
  s.q = q + static_cast<std::uint32_t>(last);
  s.p = p + 16;
  return true;
}

// verticalGroupsAvx2 sixteen samples a step.
__attribute__((target("avx512f"))) void verticalGroupsAvx512(const float* __restrict az, std::int32_t* __restrict up,
                                                            VerticalStream& s0, VerticalStream& s1)
{
  while (verticalGroup16(az, up, s0) & verticalGroup16(az, up, s1))
  {
  }
}
__attribute__((target("avx512f"))) void verticalGroupsAvx512(const float* __restrict az, std::int32_t* __restrict up,
                                                            VerticalStream& s0)
{
  while (verticalGroup16(az, up, s0))
  {
  }
}
RC_AVX512_END
#endif

// Organized: the grid position of the point one row up of each position p < m.
RC_SIMD_CLONES void upOrganized(std::size_t m, std::size_t width, const std::uint32_t* __restrict index,
                                const std::int32_t* __restrict grid_pos, std::int32_t* __restrict up)
{
  for (std::size_t p = 0; p < m; ++p) up[p] = grid_pos[index[p] + width];
}

}  // namespace

void ScanGridBuilder::findVerticalNeighbours(ScanGrid& grid)
{
  const std::size_t m = grid.size();
  if (grid.organized)
  {
    // The same column one row up: its grid position, which is -1 for a point off the grid (an
    // organized cloud has no duplicates, and the input pass set every point's to -1 before the
    // grid positions were written), so no test per point; the top ring has no row above.
    grid.up.resize(m);
    const std::size_t width = grid.num_input / static_cast<std::size_t>(grid.num_rings);
    const std::uint32_t top = grid.ring_begin[static_cast<std::size_t>(grid.num_rings) - 1];
    upOrganized(top, width, grid.index.data(), grid.grid_pos.data(), grid.up.data());
    std::fill(grid.up.begin() + top, grid.up.end(), -1);
    return;
  }
  // Every position of a ring followed by a non-empty one is written below; only the others are
  // filled with -1 (a fill of all of them first wrote every entry twice).
  grid.up.resize(m);
  // Two sorted sequences: walk them together to the last sample above at or before each
  // azimuth, then take the nearest of it, its successor (around the seam) and the last one.
  // The walk only stores where it stopped (in `up`); the choice is a loop of its own that
  // vectorizes (nearestAbove): in one loop with the walk, the search took 1.7 times the
  // instructions. With AVX2, groups of eight samples take both steps at once, without the walk's
  // branch per step (verticalGroupsAvx2; on the 29k-point frames the two functions' time halves),
  // and only the groups it cannot take go through the walk. With AVX-512, sixteen at a time
  // (verticalGroupsAvx512; ab_core grid 0.955 on KITTI, 0.97 on the 29k frames).
  const float* const az = grid.azimuth.data();
  std::int32_t* const up = grid.up.data();
#if defined(RC_SIMD_CLONES_ON)
  const bool avx2 = __builtin_cpu_supports("avx2");
  // sixteen samples a step (verticalGroupsAvx512), eight where its window does not hold
  const bool avx512 = detail::avx512Forms();
  // Two rings at a time (see verticalGroupsAvx2); a group the vector path cannot take goes
  // through the walk, and the rest of the ring back to the vector path.
  const auto searchPair = [&](VerticalStream& s0, VerticalStream& s1) {
    while (s0.p < s0.e || s1.p < s1.e)
    {
      if (s0.p < s0.e && s1.p < s1.e)
        avx512 ? verticalGroupsAvx512(az, up, s0, s1) : verticalGroupsAvx2(az, up, s0, s1);
      else
        avx512 ? verticalGroupsAvx512(az, up, s0.p < s0.e ? s0 : s1)
               : verticalGroupsAvx2(az, up, s0.p < s0.e ? s0 : s1);
      for (VerticalStream* s : {&s0, &s1})
        if (s->stuck) verticalWalk(az, up, *s, 8);
    }
  };
  VerticalStream held{0, 0, 0, 0, 0, false};  // a ring waiting for a second one
#endif
  for (int n = 0; n + 1 < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    const std::uint32_t ub = e, ue = grid.ring_begin[static_cast<std::size_t>(n) + 2];
    if (ub == ue)
    {
      std::fill(up + b, up + e, -1);
      continue;
    }
    VerticalStream s{b, e, ub, ue, ub, false};
#if defined(RC_SIMD_CLONES_ON)
    if (avx2)
    {
      if (held.p == held.e)
      {
        held = s;
      }
      else
      {
        searchPair(held, s);
        held = VerticalStream{0, 0, 0, 0, 0, false};
      }
      continue;
    }
#endif
    verticalWalk(az, up, s, e - b);
  }
#if defined(RC_SIMD_CLONES_ON)
  VerticalStream none{0, 0, 0, 0, 0, false};
  if (held.p < held.e) searchPair(held, none);
#endif
  if (grid.num_rings > 0)  // the top ring has none above it
    std::fill(up + grid.ring_begin[static_cast<std::size_t>(grid.num_rings) - 1], up + m, -1);
}

}  // namespace ring_curvature
