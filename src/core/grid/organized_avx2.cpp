// The organized float32 input pass with AVX2 intrinsics: eight columns of a row read, their
// ranges, validity and azimuths formed and the valid ones placed on the grid, in one pass. Each
// lane repeats placeColumn's operations (organized_placement.cpp), so the bits are the portable's.
// Kept: alone it gains over 10 % of the pipeline on organized frames (docs/performance.md).
#include "grid/organized_avx2.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include "common/compress_table.hpp"
#include "ring_curvature/prefetch.hpp"

#include <immintrin.h>

#include <algorithm>

namespace ring_curvature
{
namespace detail
{
namespace
{
// fastAtan2 (common/float_bits.hpp) eight lanes at a time, operation for operation. AVX2 has only
// signed 32-bit compares; they agree with the unsigned ones here (|x|, |y| have a clear sign bit,
// and "x < 0" is "bits in (0x80000000, 0xff800000]", signed (INT_MIN, -0x800000]).
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
  const __m256 a = _mm256_div_ps(_mm256_castsi256_ps(mn),
                                 _mm256_blendv_ps(one, _mm256_castsi256_ps(mx), _mm256_castsi256_ps(nonzero)));
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

// Records k and k + 4 (`step` bytes apart from p), 16 bytes of each: x y z . | x y z .
__attribute__((target("avx2"))) inline __m256 recordPairAvx2(const std::uint8_t* p, std::size_t step, std::size_t k)
{
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(reinterpret_cast<const float*>(p + k * step))),
                              _mm_loadu_ps(reinterpret_cast<const float*>(p + (k + 4) * step)), 1);
}

// x, y, z of eight records, each record's 16 bytes at its x in one load, then transposed: plain
// loads and shuffles, which every AVX2 CPU runs fast (gathers are microcoded on some).
__attribute__((target("avx2"))) inline void loadXyzAvx2(const std::uint8_t* p, std::size_t step, __m256& x, __m256& y,
                                                        __m256& z)
{
  const __m256 a0 = recordPairAvx2(p, step, 0), a1 = recordPairAvx2(p, step, 1);
  const __m256 a2 = recordPairAvx2(p, step, 2), a3 = recordPairAvx2(p, step, 3);
  const __m256 xy01 = _mm256_unpacklo_ps(a0, a1), xy23 = _mm256_unpacklo_ps(a2, a3);
  const __m256 z01 = _mm256_unpackhi_ps(a0, a1), z23 = _mm256_unpackhi_ps(a2, a3);
  x = _mm256_shuffle_ps(xy01, xy23, 0x44);
  y = _mm256_shuffle_ps(xy01, xy23, 0xEE);
  z = _mm256_shuffle_ps(z01, z23, 0x44);
}

// The 32 bits at p + j step for j in [0, 8).
__attribute__((target("avx2"))) inline __m256i load32Avx2(const std::uint8_t* p, std::size_t step)
{
  const auto four = [p, step](std::size_t k) {
    const __m128i a = _mm_loadu_si32(p + k * step), b = _mm_loadu_si32(p + (k + 1) * step);
    const __m128i c = _mm_loadu_si32(p + (k + 2) * step), d = _mm_loadu_si32(p + (k + 3) * step);
    return _mm_unpacklo_epi64(_mm_unpacklo_epi32(a, b), _mm_unpacklo_epi32(c, d));
  };
  return _mm256_inserti128_si256(_mm256_castsi128_si256(four(0)), four(4), 1);
}

// For a 4-bit mask, the 32-bit lanes that move its marked 64-bit elements to the front: 2 l and
// 2 l + 1 for each element l that kCompress lists (left-packing doubles).
__attribute__((target("avx2"))) inline __m256i pairLanes(unsigned mask4)
{
  const __m256i l = _mm256_cvtepi32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(kCompress.lane[mask4])));
  const __m256i twice = _mm256_add_epi64(l, l);
  return _mm256_or_si256(twice, _mm256_slli_epi64(_mm256_add_epi64(twice, _mm256_set1_epi64x(1)), 32));
}

// Eight columns, input indices [i, i + 8), onto the grid at w: the valid lanes moved to the front
// by the compress tables and stored whole (the arrays have room for 8 past the end), the grid
// positions in input order, and z / range of the valid lanes added to `s` in column order (+0
// for the others: s is never -0, so the same bits). Returns the number placed.
__attribute__((target("avx2,popcnt"), always_inline)) inline unsigned placeEightAvx2(
    const OrganizedGrid& out, std::size_t i, std::size_t w, __m256 x, __m256 y, __m256 z, __m256 az, __m256d r0,
    __m256d r1, __m256i valid, double& s)
{
  const auto mask = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(valid)));
  const __m256i perm = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompress.lane[mask]));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.index + w),
                      _mm256_add_epi32(perm, _mm256_set1_epi32(static_cast<int>(i))));
  _mm256_storeu_ps(out.az + w, _mm256_permutevar8x32_ps(az, perm));
  const __m256 xp = _mm256_permutevar8x32_ps(x, perm), yp = _mm256_permutevar8x32_ps(y, perm);
  const __m256 zp = _mm256_permutevar8x32_ps(z, perm);
  _mm256_storeu_pd(out.x + w, _mm256_cvtps_pd(_mm256_castps256_ps128(xp)));
  _mm256_storeu_pd(out.x + w + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(xp, 1)));
  _mm256_storeu_pd(out.y + w, _mm256_cvtps_pd(_mm256_castps256_ps128(yp)));
  _mm256_storeu_pd(out.y + w + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(yp, 1)));
  _mm256_storeu_pd(out.z + w, _mm256_cvtps_pd(_mm256_castps256_ps128(zp)));
  _mm256_storeu_pd(out.z + w + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(zp, 1)));
  const unsigned lo = mask & 15u;
  const __m256i p0 = pairLanes(lo), p1 = pairLanes(mask >> 4);
  _mm256_storeu_ps(reinterpret_cast<float*>(out.range + w), _mm256_permutevar8x32_ps(_mm256_castpd_ps(r0), p0));
  _mm256_storeu_ps(reinterpret_cast<float*>(out.range + w + static_cast<unsigned>(__builtin_popcount(lo))),
                   _mm256_permutevar8x32_ps(_mm256_castpd_ps(r1), p1));
  // grid positions in input order: w plus the valid lanes before each, -1 for the others
  __m256i before = _mm256_add_epi32(valid, _mm256_slli_si256(valid, 4));  // minus inclusive counts
  before = _mm256_add_epi32(before, _mm256_slli_si256(before, 8));
  const __m256i carry = _mm256_shuffle_epi32(before, 0xFF);
  before = _mm256_add_epi32(before, _mm256_permute2x128_si256(carry, carry, 0x08));
  const __m256i pos = _mm256_sub_epi32(_mm256_set1_epi32(static_cast<int>(w) - 1), before);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.grid_pos + i), _mm256_blendv_epi8(_mm256_set1_epi32(-1), pos, valid));
  const __m256d v0 = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(valid)));
  const __m256d v1 = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(valid, 1)));
  const __m256d q0 = _mm256_and_pd(v0, _mm256_div_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(z)), r0));
  const __m256d q1 = _mm256_and_pd(v1, _mm256_div_pd(_mm256_cvtps_pd(_mm256_extractf128_ps(z, 1)), r1));
  for (const __m256d q : {q0, q1})
  {
    const __m128d a = _mm256_castpd256_pd128(q), b = _mm256_extractf128_pd(q, 1);
    s += _mm_cvtsd_f64(a);
    s += _mm_cvtsd_f64(_mm_unpackhi_pd(a, a));
    s += _mm_cvtsd_f64(b);
    s += _mm_cvtsd_f64(_mm_unpackhi_pd(b, b));
  }
  return static_cast<unsigned>(__builtin_popcount(mask));
}

}  // namespace

__attribute__((target("avx2,popcnt"))) std::size_t readPlaceRowAvx2(const std::uint8_t* row, const RecordLayout& L,
                                                                      const OrganizedGrid& out, std::size_t i0,
                                                                      std::size_t cols, std::size_t w, double& sum,
                                                                      std::uint32_t& largest)
{
  const __m256d lo = _mm256_set1_pd(L.rmin), hi = _mm256_set1_pd(L.rmax);
  const __m256i one = _mm256_set1_epi32(static_cast<int>(PointState::OnGrid));
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  __m256i most = _mm256_setzero_si256();
  double s = sum;
  for (std::size_t c = 0; c + 8 <= cols; c += 8)
  {
    const std::size_t i = i0 + c;
    prefetchRecords(row, c + kRecordsAhead, 8, L.step, L.ox);
    __m256 x, y, z;
    loadXyzAvx2(row + c * L.step + L.ox, L.step, x, y, z);
    const __m256d r0 = range4Avx2(_mm256_castps256_ps128(x), _mm256_castps256_ps128(y), _mm256_castps256_ps128(z));
    const __m256d r1 = range4Avx2(_mm256_extractf128_ps(x, 1), _mm256_extractf128_ps(y, 1), _mm256_extractf128_ps(z, 1));
    // valid (range >= lo and <= hi; NaN fails both) as 32-bit lane masks
    const __m256d v0 = _mm256_and_pd(_mm256_cmp_pd(r0, lo, _CMP_GE_OQ), _mm256_cmp_pd(r0, hi, _CMP_LE_OQ));
    const __m256d v1 = _mm256_and_pd(_mm256_cmp_pd(r1, lo, _CMP_GE_OQ), _mm256_cmp_pd(r1, hi, _CMP_LE_OQ));
    const __m256i valid =
        _mm256_set_m128i(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v1), low_halves)),
                         _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v0), low_halves)));
    if (L.oring >= 0)
    {
      const __m256i bits = load32Avx2(row + c * L.step + static_cast<std::size_t>(L.oring), L.step);
      most = _mm256_max_epu32(most, _mm256_and_si256(bits, _mm256_set1_epi32(0xFFFF)));
    }
    const __m256i s32 = _mm256_and_si256(valid, one);  // OnGrid (1) or Invalid (0) per lane
    const __m128i s16 = _mm_packs_epi32(_mm256_castsi256_si128(s32), _mm256_extracti128_si256(s32, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out.state + i), _mm_packs_epi16(s16, s16));
    w += placeEightAvx2(out, i, w, x, y, z, fastAtan2Avx2(y, x), r0, r1, valid, s);
  }
  alignas(32) std::uint32_t l[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(l), most);
  for (const std::uint32_t v : l) largest = std::max(largest, v);
  sum = s;
  return w;
}

}  // namespace detail
}  // namespace ring_curvature
#endif
