// AVX-512 kernels of the unorganized clouds' input pass (grid_input.cpp): sixteen points'
// azimuths, ranges and validity, each lane the operations of the scalar code (scan_grid.hpp's
// fastAtan2, grid_input.cpp's storePoint) and of input_avx2.hpp's eight-lane forms, so bit for
// bit their results. Only AVX-512F: comparisons give mask registers, blends take them.
#pragma once

#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

// fastAtan2Avx2 sixteen lanes at a time (its comments say why the compares are signed ones).
// AVX-512F has no float and/xor (AVX-512DQ has), so those are integer operations on the bits.
__attribute__((target("avx512f"))) inline __m512 fastAtan2Avx512(__m512 y, __m512 x)
{
  const __m512i sign = _mm512_set1_epi32(static_cast<int>(0x80000000u));
  const __m512i above_inf = _mm512_set1_epi32(0x7f800001);  // bits < above_inf: not above +inf
  const __m512i sx = _mm512_castps_si512(x), sy = _mm512_castps_si512(y);
  const __m512i bx = _mm512_andnot_si512(sign, sx), by = _mm512_andnot_si512(sign, sy);  // |x|, |y|
  const __mmask16 x_lt_y = _mm512_cmpgt_epi32_mask(by, bx) & _mm512_cmpgt_epi32_mask(above_inf, by);
  const __mmask16 y_lt_x = _mm512_cmpgt_epi32_mask(bx, by) & _mm512_cmpgt_epi32_mask(above_inf, bx);
  const __m512i mx = _mm512_mask_blend_epi32(x_lt_y, bx, by), mn = _mm512_mask_blend_epi32(y_lt_x, bx, by);
  const __mmask16 nonzero =
      _mm512_cmpgt_epi32_mask(mx, _mm512_setzero_si512()) & _mm512_cmpgt_epi32_mask(above_inf, mx);
  const __m512 one = _mm512_set1_ps(1.0f);
  const __m512 a = _mm512_div_ps(_mm512_castsi512_ps(mn), _mm512_mask_blend_ps(nonzero, one, _mm512_castsi512_ps(mx)));
  const __m512 s = _mm512_mul_ps(a, a);
  __m512 r = _mm512_sub_ps(_mm512_mul_ps(_mm512_set1_ps(0.0208351f), s), _mm512_set1_ps(0.0851330f));
  r = _mm512_add_ps(_mm512_mul_ps(r, s), _mm512_set1_ps(0.1801410f));
  r = _mm512_sub_ps(_mm512_mul_ps(r, s), _mm512_set1_ps(0.3302995f));
  r = _mm512_add_ps(_mm512_mul_ps(r, s), _mm512_set1_ps(0.9998660f));
  r = _mm512_mul_ps(r, a);
  r = _mm512_mask_blend_ps(x_lt_y, r, _mm512_sub_ps(_mm512_set1_ps(1.57079637f), r));
  const __m512i neg_limit = _mm512_set1_epi32(static_cast<int>(0xff800001u));  // bits <= 0xff800000
  const __mmask16 x_neg = _mm512_cmpgt_epi32_mask(sx, sign) & _mm512_cmpgt_epi32_mask(neg_limit, sx);
  const __mmask16 y_neg = _mm512_cmpgt_epi32_mask(sy, sign) & _mm512_cmpgt_epi32_mask(neg_limit, sy);
  r = _mm512_mask_blend_ps(x_neg, r, _mm512_sub_ps(_mm512_set1_ps(3.14159265358979f), r));
  r = _mm512_castsi512_ps(_mm512_mask_xor_epi32(_mm512_castps_si512(r), y_neg, _mm512_castps_si512(r), sign));
  return _mm512_maskz_mov_ps(nonzero, r);
}

// The 3-D ranges of eight points: x, y, z widened to double, sqrt((x x + y y) + z z).
__attribute__((target("avx512f"))) inline __m512d range8Avx512(__m256 x8, __m256 y8, __m256 z8)
{
  const __m512d x = _mm512_cvtps_pd(x8), y = _mm512_cvtps_pd(y8), z = _mm512_cvtps_pd(z8);
  return _mm512_sqrt_pd(_mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(x, x), _mm512_mul_pd(y, y)), _mm512_mul_pd(z, z)));
}

// Valid lanes (range >= lo and range <= hi; NaN fails both) of eight ranges.
__attribute__((target("avx512f"))) inline __mmask8 valid8Avx512(__m512d r, __m512d lo, __m512d hi)
{
  return _mm512_cmp_pd_mask(r, lo, _CMP_GE_OQ) & _mm512_cmp_pd_mask(r, hi, _CMP_LE_OQ);
}

// A plain-load form of the gathers (input_avx2.hpp's loadXyzNext32Avx2 sixteen records at a
// time), where x, y, z are one run of floats and the ring lies in the 32 bytes from x:
// the loads and shuffles move bits, so these are the gathers' lanes bit for bit.
//
// Whether loadXyzNext32Avx512 reads a layout's x, y, z and ring: y and z follow x, and the ring's
// 16 bits lie in one 4-byte word of the 16 bytes after z's (then they end 18 bytes past x or more,
// the bound its callers' last-record rule rests on).
inline bool next32Layout(std::size_t ox, std::size_t oy, std::size_t oz, std::size_t oring, bool has_ring)
{
  return has_ring && oy == ox + 4 && oz == ox + 8 && oring >= ox + 16 && oring - ox <= 30 && (oring - ox) % 4 <= 2;
}

// The `pick` index of next32PickAvx512: from records k, k + 1 (32 bytes each from their x, lanes
// 0-7 and 8-15) and k + 2, k + 3 (16-31), the x, y, z and the 32 bits `word` floats past x of the
// four, as four blocks of four lanes.
__attribute__((target("avx512f"))) inline __m512i next32PickAvx512(int word)
{
  return _mm512_add_epi32(_mm512_setr_epi32(0, 8, 16, 24, 1, 9, 17, 25, 2, 10, 18, 26, 0, 8, 16, 24),
                          _mm512_maskz_set1_epi32(0xF000, word));
}
// Records k and k + 1 (`step` bytes apart from p), 32 bytes of each.
__attribute__((target("avx512f"))) inline __m512 record32PairAvx512(const std::uint8_t* p, std::size_t step,
                                                                    std::size_t k)
{
  const __m256d a = _mm256_loadu_pd(reinterpret_cast<const double*>(p + k * step));
  const __m256d b = _mm256_loadu_pd(reinterpret_cast<const double*>(p + (k + 1) * step));
  return _mm512_castpd_ps(_mm512_insertf64x4(_mm512_castpd256_pd512(a), b, 1));
}
// x, y, z and the picked 32 bits (`pick`: next32PickAvx512) of sixteen records `step` bytes
// apart, x of the first at p: each record's 32 bytes from its x in one load (SPR's gathers of
// sixteen are 16 loads each, 64 a group with the ring's), groups of four records made x x x x
// | y y y y | z z z z | w w w w by one two-source permute, then the four groups' blocks
// transposed. The caller keeps every load inside the data.
__attribute__((target("avx512f"))) inline void loadXyzNext32Avx512(const std::uint8_t* p, std::size_t step,
                                                                   __m512i pick, __m512& x, __m512& y, __m512& z,
                                                                   __m512i& next)
{
  __m512 c[4];
  for (std::size_t m = 0; m < 4; ++m)
    c[m] = _mm512_permutex2var_ps(record32PairAvx512(p, step, 4 * m), pick, record32PairAvx512(p, step, 4 * m + 2));
  // t0, t2: x y x y blocks of records 0-7, 8-15; t1, t3: z w z w
  const __m512 t0 = _mm512_shuffle_f32x4(c[0], c[1], 0x44), t1 = _mm512_shuffle_f32x4(c[0], c[1], 0xEE);
  const __m512 t2 = _mm512_shuffle_f32x4(c[2], c[3], 0x44), t3 = _mm512_shuffle_f32x4(c[2], c[3], 0xEE);
  x = _mm512_shuffle_f32x4(t0, t2, 0x88);
  y = _mm512_shuffle_f32x4(t0, t2, 0xDD);
  z = _mm512_shuffle_f32x4(t1, t3, 0x88);
  next = _mm512_castps_si512(_mm512_shuffle_f32x4(t1, t3, 0xDD));
}

}  // namespace detail
}  // namespace ring_curvature
#endif
