// The nearest sample on the ring above each grid position (ScanGrid::up): a merge walk along two
// sorted rings and the choice among three candidates for unorganized clouds, the same column one
// row up for organized ones.
#include "ring_curvature/scan_grid.hpp"

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
constexpr float kPi = 3.14159265358979f;
constexpr float kTwoPi = 6.28318530717959f;

// The nearest sample above each position p of a ring (b, e), with up[p] the last sample of the
// ring above (ub, ue) at or before p's azimuth (or ub): of up[p], its successor (around the
// seam) and the ring's last one, the nearest azimuth circularly, the first of equals in that
// order. Branch-free: which one wins is a coin toss per point. |wrapPi(d)| for |d| < 2 pi is
// |d| or 2 pi - |d|, the same float operations.
RC_SIMD_CLONES void nearestAbove(std::uint32_t b, std::uint32_t e, std::uint32_t ub, std::uint32_t ue,
                                 const float* __restrict az, std::int32_t* __restrict up)
{
  const auto circDist = [](float d) {
    const float a = std::fabs(d);
    return a > kPi ? kTwoPi - a : a;
  };
  const float last = az[ue - 1];
  for (std::uint32_t p = b; p < e; ++p)
  {
    const float a = az[p];
    const std::uint32_t q = static_cast<std::uint32_t>(up[p]);
    const std::uint32_t c1 = q + 1 < ue ? q + 1 : ub;
    const float d0 = circDist(az[q] - a), d1 = circDist(az[c1] - a), d2 = circDist(last - a);
    std::uint32_t best = d1 < d0 ? c1 : q;
    const float bd = d1 < d0 ? d1 : d0;
    best = d2 < bd ? ue - 1 : best;
    up[p] = static_cast<std::int32_t>(best);
  }
}

#if defined(RC_SIMD_CLONES_ON)
// |wrapPi(d)| eight lanes at a time, nearestAbove's circDist operation for operation.
__attribute__((target("avx2"))) inline __m256 circDist8(__m256 d)
{
  const __m256 a = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), d);
  const __m256 wrap = _mm256_cmp_ps(a, _mm256_set1_ps(kPi), _CMP_GT_OQ);
  return _mm256_blendv_ps(a, _mm256_sub_ps(_mm256_set1_ps(kTwoPi), a), wrap);
}

// The merge walk and nearestAbove's choice for eight samples p of ring (b, e) at a time, where
// the walk's exit was a data-dependent branch per sample. With q the walk's position before the
// eight (the last sample above at or before the previous one), each one's stop is q plus how
// many of az[q + 1 .. q + 16] lie at or below its azimuth: the walk stops at the first sample
// above that does not, and those sixteen are sorted, so this is the same count. It holds when
// the count stays below 16 (the stop lies inside the window), the window lies inside the ring
// above (no seam candidate but the last) and no azimuth in it or among the eight is NaN (which
// would stop the walk early); other groups go through the walk (`up` holds the stops, and the
// caller's nearestAbove chooses). The three candidates' azimuths are picked from the window's
// registers by the count. Returns the first sample not done; q is the walk's position there.
__attribute__((target("avx2"))) std::uint32_t verticalGroupsAvx2(std::uint32_t b, std::uint32_t e,
                                                                 std::uint32_t ue, const float* __restrict az,
                                                                 std::int32_t* __restrict up, std::uint32_t& q_io)
{
  std::uint32_t q = q_io, p = b;
  const __m256 last = _mm256_set1_ps(az[ue - 1]);
  const __m256i last_pos = _mm256_set1_epi32(static_cast<std::int32_t>(ue - 1));
  for (; p + 8 <= e && q + 16 < ue; p += 8)
  {
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
    if (_mm256_movemask_ps(bad) != 0) break;
    // az[q + cnt] and az[q + cnt + 1]: lanes 0..7 of the first register or (cnt >= 8) the second
    const __m256 hi = _mm256_castsi256_ps(_mm256_slli_epi32(cnt, 28));
    const __m256 aq = _mm256_blendv_ps(_mm256_permutevar8x32_ps(w0, cnt), _mm256_permutevar8x32_ps(w1, cnt), hi);
    const __m256 an = _mm256_blendv_ps(_mm256_permutevar8x32_ps(s0, cnt), _mm256_permutevar8x32_ps(s1, cnt), hi);
    const __m256 d0 = circDist8(_mm256_sub_ps(aq, a)), d1 = circDist8(_mm256_sub_ps(an, a));
    const __m256 d2 = circDist8(_mm256_sub_ps(last, a));
    const __m256 m1 = _mm256_cmp_ps(d1, d0, _CMP_LT_OQ);
    const __m256i pos = _mm256_add_epi32(_mm256_set1_epi32(static_cast<std::int32_t>(q)), cnt);
    const __m256i best = _mm256_sub_epi32(pos, _mm256_castps_si256(m1));  // + 1 where the successor is nearer
    const __m256 bd = _mm256_blendv_ps(d0, d1, m1);
    const __m256 m2 = _mm256_cmp_ps(d2, bd, _CMP_LT_OQ);
    const __m256 chosen = _mm256_blendv_ps(_mm256_castsi256_ps(best), _mm256_castsi256_ps(last_pos), m2);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(up + p), _mm256_castps_si256(chosen));
    q += static_cast<std::uint32_t>(_mm256_extract_epi32(cnt, 7));
  }
  q_io = q;
  return p;
}
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
  // and only the groups it cannot take go through the walk.
  const float* const az = grid.azimuth.data();
  std::int32_t* const up = grid.up.data();
#if defined(RC_SIMD_CLONES_ON)
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx2 = false;
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
    std::uint32_t q = ub, p = b;
    while (p < e)
    {
#if defined(RC_SIMD_CLONES_ON)
      if (avx2) p = verticalGroupsAvx2(p, e, ue, az, up, q);
#endif
      if (p == e) break;
      // the walk for a group the vector path could not take (or for all, without AVX2)
      const std::uint32_t stop = avx2 ? std::min(e, p + 8) : e;
      const std::uint32_t done = p;
      for (; p < stop; ++p)
      {
        const float a = az[p];
        while (q + 1 < ue && az[q + 1] <= a) ++q;
        up[p] = static_cast<std::int32_t>(q);
      }
      nearestAbove(done, p, ub, ue, az, up);
    }
  }
  if (grid.num_rings > 0)  // the top ring has none above it
    std::fill(up + grid.ring_begin[static_cast<std::size_t>(grid.num_rings) - 1], up + m, -1);
}

}  // namespace ring_curvature
