// AVX-512F forms of two ring sort loops that compute (ring_sort.cpp): the sort keys and the
// arrival steps. Each lane does the scalar code's operations, so the bits are the same; each
// returns how far it got, and the clones do the rest (and run on other CPUs).
// Only AVX-512F: comparisons give mask registers, the 32-bit halves of the keys move by vpermt2d.
// (Not the split of the sorted keys: with its 64-byte stores unaligned the grid took 1.02-1.06 of
// its time, aligned 1.00-1.02. Nor the ring stretch test, the ascending appends or
// removeDuplicates' stretch test: within 1.00 +- 0.015 on KITTI, in-process A/B.)
#pragma once

#include "angles.hpp"
#include "ring_curvature/prefetch.hpp"
#include "simd_clones.hpp"

#include <cstddef>
#include <cstdint>

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>

namespace ring_curvature
{
namespace detail
{
RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)

// A key's azimuth bits from its top half (keyAzimuth): top bit set, clear it; else all bits flip.
__attribute__((target("avx512f"))) inline __m512i keyAzimuthBitsAvx512(__m512i k)
{
  const __m512i sign = _mm512_set1_epi32(static_cast<int>(0x80000000u));
  const __m512i keep = _mm512_srai_epi32(k, 31);  // all ones where the top bit is set
  return _mm512_xor_si512(k, _mm512_or_si512(_mm512_andnot_si512(keep, _mm512_set1_epi32(-1)), sign));
}

// The top halves (azimuth keys) of sixteen keys at q[0, 16), in key order.
__attribute__((target("avx512f"))) inline __m512i keyTopsAvx512(const std::uint64_t* q)
{
  const __m512i a = _mm512_loadu_si512(q), b = _mm512_loadu_si512(q + 8);
  return _mm512_permutex2var_epi32(a, _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31), b);
}

// splitKeys sixteen keys at a time: index[p] = the key's low half, az[p] = its azimuth (the
// same bits as keyAzimuth). Returns the keys done (whole groups of sixteen). The split writes the
// frame's grid order a ring at a time, to lines last written a frame ago: the lines kWriteAhead
// keys ahead of both stores are asked for.
__attribute__((target("avx512f"))) inline std::size_t splitKeysAvx512(std::size_t m, const std::uint64_t* keys,
                                                                      std::uint32_t* index, float* az)
{
  const __m512i lows = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  std::size_t p = 0;
  for (; p + 16 <= m; p += 16)
  {
    prefetchForWrite(index, (p + kWriteAhead) * sizeof *index);
    prefetchForWrite(az, (p + kWriteAhead) * sizeof *az);
    const __m512i a = _mm512_loadu_si512(keys + p), b = _mm512_loadu_si512(keys + p + 8);
    _mm512_storeu_si512(index + p, _mm512_permutex2var_epi32(a, lows, b));
    _mm512_storeu_si512(az + p, keyAzimuthBitsAvx512(keyTopsAvx512(keys + p)));
  }
  return p;
}

// sortKeys sixteen points at a time: key[j] = (orderedKey(az[j] + 0), i0 + j). Returns the
// points done (whole groups of sixteen).
__attribute__((target("avx512f"))) inline std::size_t sortKeysAvx512(const float* az, std::size_t i0, std::size_t len,
                                                                     std::uint64_t* key)
{
  const __m512i sign = _mm512_set1_epi32(static_cast<int>(0x80000000u));
  const __m512i lo = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  const __m512i hi = _mm512_setr_epi32(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
  // (the index as the scalar code's static_cast<std::uint32_t>(i0 + j): modulo 2^32)
  __m512i idx = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(i0))),
                                 _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  std::size_t j = 0;
  for (; j + 16 <= len; j += 16)
  {
    // The two lines kWriteAhead keys ahead asked for (prefetch.hpp): rings one after another
    // (KITTI) write the frame's keys here in one stream, to lines last written a frame ago.
    // (Blocks of the interleaved scatter go to a buffer on the stack: two prefetches wasted.)
    prefetchForWrite(key, (j + kWriteAhead) * sizeof *key);
    prefetchForWrite(key, (j + kWriteAhead + 8) * sizeof *key);
    const __m512i u = _mm512_castps_si512(_mm512_add_ps(_mm512_loadu_ps(az + j), _mm512_setzero_ps()));
    const __m512i k = _mm512_xor_si512(u, _mm512_or_si512(_mm512_srai_epi32(u, 31), sign));  // orderedKey
    _mm512_storeu_si512(key + j, _mm512_permutex2var_epi32(idx, lo, k));
    _mm512_storeu_si512(key + j + 8, _mm512_permutex2var_epi32(idx, hi, k));
    idx = _mm512_add_epi32(idx, _mm512_set1_epi32(16));
  }
  return j;
}

// arrivalSteps sixteen steps at a time from j = 1: step[j], wide[j] and the count of steps down.
// Returns the first step not done (the caller's loop goes on from there).
__attribute__((target("avx512f"))) inline std::size_t arrivalStepsAvx512(const std::uint64_t* src, std::size_t k,
                                                                         float* step, std::uint8_t* wide,
                                                                         std::uint32_t& down)
{
  std::size_t j = 1;
  if (k < 17) return j;
  // prev: the azimuths of the sixteen keys before, of which lane 15 is used
  __m512 prev = _mm512_castsi512_ps(keyAzimuthBitsAvx512(_mm512_set1_epi32(static_cast<int>(src[0] >> 32))));
  const __m512 pi = _mm512_set1_ps(kPi), minus_pi = _mm512_set1_ps(-kPi), zero = _mm512_setzero_ps();
  const __m512i one = _mm512_set1_epi32(1);
  __m512i count = _mm512_setzero_si512();
  for (; j + 16 <= k; j += 16)
  {
    const __m512 cur = _mm512_castsi512_ps(keyAzimuthBitsAvx512(keyTopsAvx512(src + j)));
    const __m512 before =
        _mm512_castsi512_ps(_mm512_alignr_epi32(_mm512_castps_si512(cur), _mm512_castps_si512(prev), 15));
    const __m512 d = _mm512_sub_ps(cur, before);
    _mm512_storeu_ps(step + j, d);
    const __mmask16 w = _mm512_cmp_ps_mask(d, minus_pi, _CMP_LT_OQ) | _mm512_cmp_ps_mask(d, pi, _CMP_GT_OQ);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(wide + j), _mm512_cvtepi32_epi8(_mm512_maskz_mov_epi32(w, one)));
    count = _mm512_mask_add_epi32(count, _mm512_cmp_ps_mask(d, zero, _CMP_LT_OQ), count, one);
    prev = cur;
  }
  down += static_cast<std::uint32_t>(_mm512_reduce_add_epi32(count));
  return j;
}

RC_AVX512_END

}  // namespace detail
}  // namespace ring_curvature
#endif
