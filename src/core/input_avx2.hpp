// AVX2 kernels of the grid's input passes over float32 records (grid_input.cpp for the
// unorganized clouds, grid_organized.cpp for the organized ones): eight points' azimuths, ranges
// and validity, each lane the operations of the scalar code (scan_grid.hpp's fastAtan2,
// grid_input.cpp's storePoint), so bit for bit its results.
#pragma once

#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>

#include "cpu_tuning.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

// fastAtan2 (scan_grid.hpp) eight lanes at a time, operation for operation, so bit for bit the
// same: the comparisons on bit patterns are signed ones here (AVX2 has no unsigned 32-bit
// compare), which agree with the unsigned ones for these operands (|x| and |y| have a clear sign
// bit; "x < 0" is "bits in (0x80000000, 0xff800000]", i.e. signed in (INT_MIN, -0x800000]).
__attribute__((target("avx2"))) inline __m256 fastAtan2Avx2(__m256 y, __m256 x)
{
  const __m256i sign = _mm256_set1_epi32(static_cast<int>(0x80000000u));
  const __m256i above_inf = _mm256_set1_epi32(0x7f800001);  // bits < above_inf: not above +inf
  const __m256i sx = _mm256_castps_si256(x), sy = _mm256_castps_si256(y);
  const __m256i bx = _mm256_andnot_si256(sign, sx), by = _mm256_andnot_si256(sign, sy);  // |x|, |y|
  const __m256i x_lt_y = _mm256_and_si256(_mm256_cmpgt_epi32(by, bx), _mm256_cmpgt_epi32(above_inf, by));
  const __m256i y_lt_x = _mm256_and_si256(_mm256_cmpgt_epi32(bx, by), _mm256_cmpgt_epi32(above_inf, bx));
  const __m256i mx = _mm256_blendv_epi8(bx, by, x_lt_y), mn = _mm256_blendv_epi8(bx, by, y_lt_x);
  const __m256i nonzero = _mm256_and_si256(_mm256_cmpgt_epi32(mx, _mm256_setzero_si256()),
                                           _mm256_cmpgt_epi32(above_inf, mx));
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 a = _mm256_div_ps(_mm256_castsi256_ps(mn), _mm256_blendv_ps(one, _mm256_castsi256_ps(mx),
                                                                          _mm256_castsi256_ps(nonzero)));
  const __m256 s = _mm256_mul_ps(a, a);
  __m256 r = _mm256_sub_ps(_mm256_mul_ps(_mm256_set1_ps(0.0208351f), s), _mm256_set1_ps(0.0851330f));
  r = _mm256_add_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.1801410f));
  r = _mm256_sub_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.3302995f));
  r = _mm256_add_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.9998660f));
  r = _mm256_mul_ps(r, a);
  r = _mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(1.57079637f), r), _mm256_castsi256_ps(x_lt_y));
  const __m256i neg_limit = _mm256_set1_epi32(static_cast<int>(0xff800001u));  // bits <= 0xff800000
  const __m256i x_neg = _mm256_and_si256(_mm256_cmpgt_epi32(sx, sign), _mm256_cmpgt_epi32(neg_limit, sx));
  const __m256i y_neg = _mm256_and_si256(_mm256_cmpgt_epi32(sy, sign), _mm256_cmpgt_epi32(neg_limit, sy));
  r = _mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(3.14159265358979f), r), _mm256_castsi256_ps(x_neg));
  r = _mm256_blendv_ps(r, _mm256_xor_ps(r, _mm256_castsi256_ps(sign)), _mm256_castsi256_ps(y_neg));
  return _mm256_and_ps(r, _mm256_castsi256_ps(nonzero));
}

// The 3-D ranges of four points: x, y, z widened to double, sqrt((x x + y y) + z z).
__attribute__((target("avx2"))) inline __m256d range4Avx2(__m128 x4, __m128 y4, __m128 z4)
{
  const __m256d x = _mm256_cvtps_pd(x4), y = _mm256_cvtps_pd(y4), z = _mm256_cvtps_pd(z4);
  return _mm256_sqrt_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z)));
}
// ... of eight points, as two vectors of four doubles.
__attribute__((target("avx2"))) inline void rangesAvx2(__m256 x, __m256 y, __m256 z, __m256d& r0, __m256d& r1)
{
  r0 = range4Avx2(_mm256_castps256_ps128(x), _mm256_castps256_ps128(y), _mm256_castps256_ps128(z));
  r1 = range4Avx2(_mm256_extractf128_ps(x, 1), _mm256_extractf128_ps(y, 1), _mm256_extractf128_ps(z, 1));
}

// Valid lanes (range >= lo and range <= hi; NaN fails both) of eight points' ranges r0, r1 as
// 32-bit masks: each half's four 64-bit masks become their low halves.
__attribute__((target("avx2"))) inline __m256i validAvx2(__m256d r0, __m256d r1, __m256d lo, __m256d hi)
{
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  const __m256d v0 = _mm256_and_pd(_mm256_cmp_pd(r0, lo, _CMP_GE_OQ), _mm256_cmp_pd(r0, hi, _CMP_LE_OQ));
  const __m256d v1 = _mm256_and_pd(_mm256_cmp_pd(r1, lo, _CMP_GE_OQ), _mm256_cmp_pd(r1, hi, _CMP_LE_OQ));
  return _mm256_set_m128i(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v1), low_halves)),
                          _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v0), low_halves)));
}

// Plain-load forms of the input passes' gathers, for CPUs where the gathers are microcoded (AMD
// Zen; cpu_tuning.hpp): loads and shuffles move bits, so these are the gathers' lanes bit for bit.

// Records k and k + 4 (`step` bytes apart from p), 16 bytes of each: x y z . | x y z .
__attribute__((target("avx2"))) inline __m256 recordPairAvx2(const std::uint8_t* p, std::size_t step, std::size_t k)
{
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(reinterpret_cast<const float*>(p + k * step))),
                              _mm_loadu_ps(reinterpret_cast<const float*>(p + (k + 4) * step)), 1);
}
// x, y, z of eight records from their x y z . quadruples, records k and k + 4 paired in a_k.
__attribute__((target("avx2"))) inline void transposeXyzAvx2(__m256 a0, __m256 a1, __m256 a2, __m256 a3, __m256& x,
                                                             __m256& y, __m256& z)
{
  const __m256 xy01 = _mm256_unpacklo_ps(a0, a1), xy23 = _mm256_unpacklo_ps(a2, a3);  // x0 x1 y0 y1 | x4 x5 y4 y5
  const __m256 z01 = _mm256_unpackhi_ps(a0, a1), z23 = _mm256_unpackhi_ps(a2, a3);    // z0 z1 . . | z4 z5 . .
  x = _mm256_shuffle_ps(xy01, xy23, 0x44);
  y = _mm256_shuffle_ps(xy01, xy23, 0xEE);
  z = _mm256_shuffle_ps(z01, z23, 0x44);
}
// x, y, z of eight records `step` bytes apart, x of the first at p and y, z the two floats after
// each x (the common layouts): each record's 16 bytes at its x in one load, the eight transposed
// (an insert, two unpacks and a shuffle and a half per vector, where a gather of eight is a few
// dozen micro-ops on Zen 3). The 4 bytes after z are read too: the caller keeps every load inside
// the data.
__attribute__((target("avx2"))) inline void loadXyzAvx2(const std::uint8_t* p, std::size_t step, __m256& x, __m256& y,
                                                        __m256& z)
{
  transposeXyzAvx2(recordPairAvx2(p, step, 0), recordPairAvx2(p, step, 1), recordPairAvx2(p, step, 2),
                   recordPairAvx2(p, step, 3), x, y, z);
}

// loadXyzAvx2 and the 32 bits 16 bytes after each x (velodyne's ring after x, y, z, intensity),
// from each record's 32 bytes at its x in one load: the low halves of records k and k + 4 paired
// and transposed as in loadXyzAvx2, the high halves' first words gathered the same way. 16 bytes
// past loadXyzAvx2's reads, one 4-byte load a record fewer.
__attribute__((target("avx2"))) inline void loadXyzNext32Avx2(const std::uint8_t* p, std::size_t step, __m256& x,
                                                              __m256& y, __m256& z, __m256i& next)
{
  __m256 lo[4], hi[4];
  for (std::size_t k = 0; k < 4; ++k)
  {
    const __m256 a = _mm256_loadu_ps(reinterpret_cast<const float*>(p + k * step));
    const __m256 b = _mm256_loadu_ps(reinterpret_cast<const float*>(p + (k + 4) * step));
    lo[k] = _mm256_permute2f128_ps(a, b, 0x20);  // x y z . of k | of k + 4
    hi[k] = _mm256_permute2f128_ps(a, b, 0x31);  // the 16 bytes after
  }
  transposeXyzAvx2(lo[0], lo[1], lo[2], lo[3], x, y, z);
  const __m256 w01 = _mm256_unpacklo_ps(hi[0], hi[1]), w23 = _mm256_unpacklo_ps(hi[2], hi[3]);
  next = _mm256_castps_si256(_mm256_shuffle_ps(w01, w23, 0x44));
}

// Whether the input passes read x, y, z with gathers: on the Intel tuning profile, and wherever
// y and z do not follow x as the plain-load forms need (cpu_tuning.hpp).
inline bool inputGathers(std::size_t ox, std::size_t oy, std::size_t oz)
{
  return avx2Gathers() || oy != ox + 4 || oz != ox + 8;
}

// The 32 bits at p + j step for j in [k, k + 4), one 4-byte load each.
__attribute__((target("avx2"))) inline __m128i load32x4Avx2(const std::uint8_t* p, std::size_t step, std::size_t k)
{
  const __m128i a = _mm_loadu_si32(p + k * step), b = _mm_loadu_si32(p + (k + 1) * step);
  const __m128i c = _mm_loadu_si32(p + (k + 2) * step), d = _mm_loadu_si32(p + (k + 3) * step);
  return _mm_unpacklo_epi64(_mm_unpacklo_epi32(a, b), _mm_unpacklo_epi32(c, d));
}
// ... for k in [0, 8): the bytes a gather of those offsets reads.
__attribute__((target("avx2"))) inline __m256i load32Avx2(const std::uint8_t* p, std::size_t step)
{
  return _mm256_inserti128_si256(_mm256_castsi128_si256(load32x4Avx2(p, step, 0)), load32x4Avx2(p, step, 4), 1);
}

}  // namespace detail
}  // namespace ring_curvature
#endif
