// The organized clouds' grid: a row is a ring and the columns are in azimuth order already, so
// placing a row's valid points is a compaction. For float32 clouds on AVX2 CPUs the input pass
// and the placement are one pass (readOrganized; sixteen columns at a time on AVX-512 CPUs, eight
// on AVX2 ones); otherwise placeOrganized places the input pass's points.
#include "ring_curvature/scan_grid.hpp"

#include "compress_table.hpp"
#include "input_avx2.hpp"
#include "input_avx512.hpp"
#include "ring_curvature/prefetch.hpp"
#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ring_curvature
{

namespace
{
#if defined(RC_SIMD_CLONES_ON)
struct OrganizedInput
{
  const std::int32_t* ring;
  const float *az, *x, *y, *z;
  const double* range;
};
struct OrganizedGrid
{
  std::uint32_t* index;  // (r W + column in row r: the grid keeps no columns of its own)
  float* az;
  double *x, *y, *z, *range;
  std::int32_t* grid_pos;
  PointState* state;  // (written by the fused input pass only)
};

// Eight columns of a row, input indices [i, i + 8), onto the grid at w: their
// coordinates, azimuths and ranges as read, `valid` the lanes to keep (all ones or zero). The
// valid lanes are moved to the front by the compress table and stored whole (the arrays have
// room for 8 past the end); the grid positions in input order; z / range of the valid lanes
// added to `s` in column order, with +0 for the others (s never is -0, so s + 0 is s: the same
// bits as adding the valid ones alone). Returns the number placed.
__attribute__((target("avx2,popcnt"), always_inline)) inline unsigned placeEightAvx2(
    const OrganizedGrid& out, std::size_t i, std::size_t w, __m256 x, __m256 y, __m256 z, __m256 az,
    __m256d r0, __m256d r1, __m256i valid, double& s)
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
  const __m256i p0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPairs.lane[lo]));
  const __m256i p1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPairs.lane[mask >> 4]));
  _mm256_storeu_ps(reinterpret_cast<float*>(out.range + w), _mm256_permutevar8x32_ps(_mm256_castpd_ps(r0), p0));
  _mm256_storeu_ps(reinterpret_cast<float*>(out.range + w + static_cast<unsigned>(__builtin_popcount(lo))),
                   _mm256_permutevar8x32_ps(_mm256_castpd_ps(r1), p1));
  // grid positions in input order: w plus the valid lanes before each, -1 for the others
  __m256i before = _mm256_add_epi32(valid, _mm256_slli_si256(valid, 4));  // minus inclusive counts
  before = _mm256_add_epi32(before, _mm256_slli_si256(before, 8));
  const __m256i carry = _mm256_shuffle_epi32(before, 0xFF);
  before = _mm256_add_epi32(before, _mm256_permute2x128_si256(carry, carry, 0x08));
  const __m256i pos = _mm256_sub_epi32(_mm256_set1_epi32(static_cast<int>(w) - 1), before);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.grid_pos + i),
                      _mm256_blendv_epi8(_mm256_set1_epi32(-1), pos, valid));
  // z / range of the valid lanes in column order
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

// The placement's store streams (eight: index, azimuth, x, y, z, range at w, the grid
// positions and states at input index i), on lines last written a frame ago
// (ring_curvature/prefetch.hpp): each one's lines for the 16 points kWriteAhead places ahead,
// asked for once every 16 columns. Without them the fused pass of readPlaceRowAvx512 waited on
// its stores as well as its records: on the OS1-128 frames it moves about 100 bytes a point,
// from and to memory (the frames, 6 MB of records each, do not stay in the caches).
// (always_inline: a function of prefetches alone has no side effects for GCC, which then deletes
// the calls to it)
__attribute__((always_inline)) inline void prefetchPlacement(const OrganizedGrid& out, std::size_t i, std::size_t w)
{
  using detail::prefetchForWrite;
  constexpr std::size_t A = detail::kWriteAhead;
  prefetchForWrite(out.index, (w + A) * sizeof(std::uint32_t));
  prefetchForWrite(out.az, (w + A) * sizeof(float));
  for (const double* d : {out.x, out.y, out.z, out.range})
  {
    prefetchForWrite(d, (w + A) * sizeof(double));
    prefetchForWrite(d, (w + A + 8) * sizeof(double));
  }
  prefetchForWrite(out.grid_pos, (i + A) * sizeof(std::int32_t));
  prefetchForWrite(out.state, i + A);  // (the same line four calls in a row: one instruction)
}

// One row (ring) of an organized float32 cloud from the input pass's arrays, columns [0, W)
// from input index i0, its valid points appended at w: the placement (index, azimuth),
// the gather of the coordinates, the grid positions and the sum of z / range in column order,
// which were three passes over the frame. Returns the new w.
__attribute__((target("avx2,popcnt"))) std::size_t placeRowAvx2(const OrganizedInput& in, const OrganizedGrid& out,
                                                                  std::size_t i0, std::size_t W, std::size_t w,
                                                                  double& sum)
{
  double s = sum;
  std::size_t c = 0;
  for (; c + 8 <= W; c += 8)
  {
    const std::size_t i = i0 + c;
    const __m256i valid = _mm256_cmpgt_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.ring + i)),
                                             _mm256_set1_epi32(-1));
    w += placeEightAvx2(out, i, w, _mm256_loadu_ps(in.x + i), _mm256_loadu_ps(in.y + i), _mm256_loadu_ps(in.z + i),
                        _mm256_loadu_ps(in.az + i), _mm256_loadu_pd(in.range + i), _mm256_loadu_pd(in.range + i + 4),
                        valid, s);
  }
  for (; c < W; ++c)
  {
    const std::size_t i = i0 + c;
    const bool ok = in.ring[i] >= 0;
    const double z = in.z[i], r = in.range[i];
    out.index[w] = static_cast<std::uint32_t>(i);
    out.az[w] = in.az[i];
    out.x[w] = in.x[i];
    out.y[w] = in.y[i];
    out.z[w] = z;
    out.range[w] = r;
    out.grid_pos[i] = ok ? static_cast<std::int32_t>(w) : -1;
    if (ok) s += z / r;
    w += ok ? 1 : 0;
  }
  sum = s;
  return w;
}
#endif


#if defined(RC_SIMD_CLONES_ON)
// Where a record's fields are, and the valid ranges (readOrganized).
struct RecordLayout
{
  std::size_t step;
  std::uint32_t ox, oy, oz;
  std::int32_t oring;  // -1: no ring field
  double rmin, rmax;
};
// One column of readPlaceRowAvx2, the same operations as a lane there (storePoint, fastAtan2,
// placeRowAvx2's tail).
inline std::size_t placeColumn(const std::uint8_t* rec, const RecordLayout& L, const OrganizedGrid& out,
                               std::size_t i, std::size_t w, double& s, std::uint32_t& largest)
{
  const float x = readFloat32(rec + L.ox), y = readFloat32(rec + L.oy), z = readFloat32(rec + L.oz);
  const double dx = x, dy = y, dz = z;
  const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
  const bool ok = (r >= L.rmin) & (r <= L.rmax);
  if (L.oring >= 0)
  {
    std::uint16_t r16;
    std::memcpy(&r16, rec + L.oring, sizeof r16);
    largest = std::max<std::uint32_t>(largest, r16);
  }
  out.state[i] = ok ? PointState::OnGrid : PointState::Invalid;
  out.index[w] = static_cast<std::uint32_t>(i);
  out.az[w] = fastAtan2(y, x);
  out.x[w] = dx;
  out.y[w] = dy;
  out.z[w] = dz;
  out.range[w] = r;
  out.grid_pos[i] = ok ? static_cast<std::int32_t>(w) : -1;
  if (ok) s += dz / r;
  return w + (ok ? 1 : 0);
}

// The input pass and the placement of one row of an organized float32 cloud in one: its
// records [0, W) (from `row`, `step` bytes apart) read and placed on the grid at w as
// placeRowAvx2 places them, with the per-point state and grid position. The input pass's per
// point arrays (33 bytes a point) are neither written nor read back: on the OS1-128 frames
// (48-byte records) the two passes moved about 160 bytes a point. Each lane computes what
// readXyzRecordsAvx2 computes (input_avx2.hpp). Columns [0, vector_cols) go eight at a time,
// the rest one at a time (placeColumn); `largest` takes the largest 16-bit ring field when
// oring >= 0. Columns before `first` (a multiple of 8) were done already (readPlaceRowAvx512).
// kGathers false: the fields read with plain loads (as readXyzRecordsAvx2<false> reads them;
// needs oy = ox + 4, oz = ox + 8). Returns the new w.
template <bool kGathers>
__attribute__((target("avx2,popcnt"))) std::size_t readPlaceRowAvx2(const std::uint8_t* row, const RecordLayout& L,
                                                                      const OrganizedGrid& out, std::size_t i0,
                                                                      std::size_t W, std::size_t first,
                                                                      std::size_t vector_cols, std::size_t w,
                                                                      double& sum, std::uint32_t& largest)
{
  const int st = static_cast<int>(L.step);
  const __m256i lanes = _mm256_setr_epi32(0, st, 2 * st, 3 * st, 4 * st, 5 * st, 6 * st, 7 * st);
  const __m256i vx = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(L.ox)));
  const __m256i vy = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(L.oy)));
  const __m256i vz = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(L.oz)));
  const __m256i vr = _mm256_add_epi32(lanes, _mm256_set1_epi32(std::max(L.oring, 0)));
  const __m256d lo = _mm256_set1_pd(L.rmin), hi = _mm256_set1_pd(L.rmax);
  const __m256i one = _mm256_set1_epi32(static_cast<int>(PointState::OnGrid));
  __m256i most = _mm256_setzero_si256();
  double s = sum;
  std::size_t c = first;
  for (; c < vector_cols; c += 8)
  {
    const std::size_t i = i0 + c;
    detail::prefetchRecords(row, c + detail::kRecordsAhead, 8, L.step, L.ox);  // (see readPlaceRowAvx512)
    if ((c & 15) == 0) prefetchPlacement(out, i, w);
    const auto* const base = reinterpret_cast<const float*>(row + c * L.step);
    __m256 x, y, z;
    if constexpr (kGathers)
    {
      x = _mm256_i32gather_ps(base, vx, 1);
      y = _mm256_i32gather_ps(base, vy, 1);
      z = _mm256_i32gather_ps(base, vz, 1);
    }
    else
      detail::loadXyzAvx2(row + c * L.step + L.ox, L.step, x, y, z);
    __m256d r0, r1;
    detail::rangesAvx2(x, y, z, r0, r1);
    const __m256i valid = detail::validAvx2(r0, r1, lo, hi);
    if (L.oring >= 0)
    {
      __m256i bits;
      if constexpr (kGathers)
        bits = _mm256_i32gather_epi32(reinterpret_cast<const int*>(base), vr, 1);
      else
        bits = detail::load32Avx2(row + c * L.step + static_cast<std::size_t>(L.oring), L.step);
      most = _mm256_max_epu32(most, _mm256_and_si256(bits, _mm256_set1_epi32(0xFFFF)));
    }
    const __m256i s32 = _mm256_and_si256(valid, one);  // OnGrid (1) or Invalid (0) per lane
    const __m128i s16 = _mm_packs_epi32(_mm256_castsi256_si128(s32), _mm256_extracti128_si256(s32, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out.state + i), _mm_packs_epi16(s16, s16));
    w += placeEightAvx2(out, i, w, x, y, z, detail::fastAtan2Avx2(y, x), r0, r1, valid, s);
  }
  alignas(32) std::uint32_t l[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(l), most);
  for (const std::uint32_t v : l) largest = std::max(largest, v);
  for (; c < W; ++c) w = placeColumn(row + c * L.step, L, out, i0 + c, w, s, largest);
  sum = s;
  return w;
}

RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// The lanes of v in `keep` moved to the front and widened to double, stored whole at `to`.
__attribute__((target("avx512f"), always_inline)) inline void compressWiden(__mmask16 keep, __m512 v, double* to)
{
  const __m512 p = _mm512_maskz_compress_ps(keep, v);
  _mm512_storeu_pd(to, _mm512_cvtps_pd(_mm512_castps512_ps256(p)));
  _mm512_storeu_pd(to + 8, _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(p), 1))));
}
// readPlaceRowAvx2's columns [0, vector_cols) (a multiple of 16) sixteen at a time with AVX-512F,
// lane by lane the same operations (input_avx512.hpp), so the same bits. The mask registers
// make the compaction a compress into a register and a full store (the arrays have room for 16
// past the end; compress-store to memory is slow on some Intel cores), and the grid positions
// an expand of w, w + 1, ... into the valid lanes. kNext32 (next32Layout: x, y, z one run of
// floats and the ring in the 32 bytes from x, as Ouster's and velodyne's records): each record's
// 32 bytes in one load (loadXyzNext32Avx512) instead of four gathers of sixteen, which on Zen 4
// took the organized grid 1.06 of the AVX2 loads' time (docs/benchmark.md, session 21); the
// caller leaves the data's last record to the columns after (its 32 bytes could pass the end).
// Returns the new w.
template <bool kNext32>
__attribute__((target("avx512f"))) std::size_t readPlaceRowAvx512(const std::uint8_t* row, const RecordLayout& L,
                                                                    const OrganizedGrid& out, std::size_t i0,
                                                                    std::size_t vector_cols, std::size_t w,
                                                                    double& sum, std::uint32_t& largest)
{
  const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  const __m512i lanes = _mm512_mullo_epi32(iota, _mm512_set1_epi32(static_cast<int>(L.step)));
  const __m512i vx = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(L.ox)));
  const __m512i vy = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(L.oy)));
  const __m512i vz = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(L.oz)));
  const __m512i vr = _mm512_add_epi32(lanes, _mm512_set1_epi32(std::max(L.oring, 0)));
  const __m512d lo = _mm512_set1_pd(L.rmin), hi = _mm512_set1_pd(L.rmax);
  const __m512i one = _mm512_set1_epi32(static_cast<int>(PointState::OnGrid)), none = _mm512_set1_epi32(-1);
  // (kNext32: the ring's word among the 32 bytes, and its bits' place in the word)
  const auto ring_at = static_cast<std::uint32_t>(std::max(L.oring, 0)) - L.ox;
  const __m512i pick = detail::next32PickAvx512(static_cast<int>(ring_at / 4));
  const __m128i ring_shift = _mm_cvtsi32_si128(static_cast<int>(ring_at % 4 * 8));
  __m512i most = _mm512_setzero_si512();
  double s = sum;
  for (std::size_t c = 0; c < vector_cols; c += 16)
  {
    const std::size_t i = i0 + c;
    // the records a few kilobytes ahead (past the row's end: the next row's, or nothing; a
    // prefetch never faults)
    detail::prefetchRecords(row, c + detail::kRecordsAhead, 16, L.step, L.ox);
    prefetchPlacement(out, i, w);
    const auto* const base = reinterpret_cast<const float*>(row + c * L.step);
    __m512 x, y, z;
    __m512i bits;  // (kNext32: the 32 bits holding the ring)
    if constexpr (kNext32)
      detail::loadXyzNext32Avx512(row + c * L.step + L.ox, L.step, pick, x, y, z, bits);
    else
    {
      x = _mm512_i32gather_ps(vx, base, 1);
      y = _mm512_i32gather_ps(vy, base, 1);
      z = _mm512_i32gather_ps(vz, base, 1);
      bits = L.oring >= 0 ? _mm512_i32gather_epi32(vr, base, 1) : _mm512_setzero_si512();
    }
    const __m256 z1 = _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(z), 1));
    const __m512d r0 = detail::range8Avx512(_mm512_castps512_ps256(x), _mm512_castps512_ps256(y),
                                            _mm512_castps512_ps256(z));
    const __m512d r1 = detail::range8Avx512(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1)),
                                            _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(y), 1)), z1);
    const __mmask8 v0 = detail::valid8Avx512(r0, lo, hi), v1 = detail::valid8Avx512(r1, lo, hi);
    const auto valid = static_cast<__mmask16>(v0 | (static_cast<unsigned>(v1) << 8));
    if (L.oring >= 0)
    {
      if constexpr (kNext32) bits = _mm512_srl_epi32(bits, ring_shift);
      most = _mm512_max_epu32(most, _mm512_and_si512(bits, _mm512_set1_epi32(0xFFFF)));
    }
    // OnGrid (1) or Invalid (0) per lane, narrowed to bytes
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out.state + i),
                     _mm512_cvtepi32_epi8(_mm512_maskz_mov_epi32(valid, one)));
    // the valid lanes moved to the front, stored whole
    const __m512i index = _mm512_add_epi32(iota, _mm512_set1_epi32(static_cast<int>(i)));
    _mm512_storeu_si512(out.index + w, _mm512_maskz_compress_epi32(valid, index));
    _mm512_storeu_ps(out.az + w, _mm512_maskz_compress_ps(valid, detail::fastAtan2Avx512(y, x)));
    compressWiden(valid, x, out.x + w);
    compressWiden(valid, y, out.y + w);
    compressWiden(valid, z, out.z + w);
    const unsigned n0 = static_cast<unsigned>(__builtin_popcount(v0));
    _mm512_storeu_pd(out.range + w, _mm512_maskz_compress_pd(v0, r0));
    _mm512_storeu_pd(out.range + w + n0, _mm512_maskz_compress_pd(v1, r1));
    // grid positions in input order: w, w + 1, ... in the valid lanes, -1 in the others
    const __m512i pos = _mm512_add_epi32(iota, _mm512_set1_epi32(static_cast<int>(w)));
    _mm512_storeu_si512(out.grid_pos + i, _mm512_mask_expand_epi32(none, valid, pos));
    // z / range of the valid lanes in column order, +0 for the others (as placeEightAvx2)
    alignas(64) double q[16];
    _mm512_store_pd(q, _mm512_maskz_div_pd(v0, _mm512_cvtps_pd(_mm512_castps512_ps256(z)), r0));
    _mm512_store_pd(q + 8, _mm512_maskz_div_pd(v1, _mm512_cvtps_pd(z1), r1));
    for (const double v : q) s += v;
    w += n0 + static_cast<unsigned>(__builtin_popcount(v1));
  }
  // (stored and read back: _mm512_reduce_max_epu32 trips GCC 12's -Wuninitialized here)
  alignas(64) std::uint32_t l[16];
  _mm512_store_si512(l, most);
  for (const std::uint32_t v : l) largest = std::max(largest, v);
  sum = s;
  return w;
}
RC_AVX512_END
#endif

}  // namespace

bool ScanGridBuilder::placeOrganized(const PointCloudView& view, ScanGrid& grid)
{
  // Row = ring, column order = azimuth order: the sensor already gives the grid.
  const std::size_t R = view.height, W = view.width;
  grid.ring_begin.assign(R + 1, 0);
#if defined(RC_SIMD_CLONES_ON)
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  if (fast && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt"))
  {
    // One pass instead of three (placement, gather, positions and sums), eight columns at a
    // time: on the OS1-128 frames they read and wrote about 11 MB, and the gather alone was
    // ~5 % of a frame.
    const std::size_t room = R * W + 8;  // the vector stores write up to 8 past the last point
    tmp_index_.resize(room);
    sorted_az_.resize(room);
    for (auto* v : {&grid.x, &grid.y, &grid.z, &grid.range}) v->resize(room);
    ring_sum_.assign(R, 0.0);
    const OrganizedInput in{ring_of_.data(), paz_.data(), px_.data(), py_.data(), pz_.data(), prange_.data()};
    const OrganizedGrid out{tmp_index_.data(), sorted_az_.data(), grid.x.data(),
                            grid.y.data(),     grid.z.data(),     grid.range.data(), grid.grid_pos.data(), nullptr};
    std::size_t w = 0;
    for (std::size_t r = 0; r < R; ++r)
    {
      w = placeRowAvx2(in, out, r * W, W, w, ring_sum_[r]);
      grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
    }
    tmp_index_.resize(w);
    sorted_az_.resize(w);
    return true;
  }
#endif
  // Branch-free compaction into presized arrays (NaN-padded sensors make validity a coin toss
  // per point): every point is written at w, only valid ones advance it.
  tmp_index_.resize(R * W + 1);
  sorted_az_.resize(R * W + 1);
  std::uint32_t* const index = tmp_index_.data();
  float* const az = sorted_az_.data();
  const std::int32_t* const ring = ring_of_.data();
  std::size_t w = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    for (std::size_t c = 0; c < W; ++c)
    {
      const std::size_t i = r * W + c;
      index[w] = static_cast<std::uint32_t>(i);
      az[w] = paz_[i];
      w += ring[i] >= 0 ? 1 : 0;
    }
    grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
  }
  tmp_index_.resize(w);
  sorted_az_.resize(w);
  return false;
}

bool ScanGridBuilder::readOrganized(const PointCloudView& view, const Params& params, ScanGrid& grid,
                                    std::uint32_t& largest)
{
#if defined(RC_SIMD_CLONES_ON)
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  const bool ring16 = !view.ring.present() || view.ring.type == ScalarType::UInt16;
  // every gather offset of a group (7 steps and a field offset) must fit an int32
  if (!fast || !ring16 || view.point_step > (1u << 26) || !__builtin_cpu_supports("avx2") ||
      !__builtin_cpu_supports("popcnt"))
    return false;
  const std::size_t R = view.height, W = view.width, n = R * W;
  grid.num_input = n;
  grid.num_rings = static_cast<int>(R);
  grid.state.resize(n + 16);  // the state stores write 16 bytes a group
  grid.grid_pos.resize(n);
  const std::size_t room = n + 16;  // the vector stores write up to 16 past the last point
  tmp_index_.resize(room);
  sorted_az_.resize(room);
  for (auto* v : {&grid.x, &grid.y, &grid.z, &grid.range}) v->resize(room);
  ring_sum_.assign(R, 0.0);
  grid.ring_begin.assign(R + 1, 0);
  const auto offset = [](const FieldView& f) { return static_cast<std::uint32_t>(f.offset); };
  const RecordLayout layout{view.point_step, offset(view.x), offset(view.y), offset(view.z),
                            view.ring.present() ? static_cast<std::int32_t>(view.ring.offset) : -1,
                            params.min_range, params.max_range};
  const OrganizedGrid out{tmp_index_.data(), sorted_az_.data(), grid.x.data(),
                          grid.y.data(),     grid.z.data(),     grid.range.data(), grid.grid_pos.data(),
                          grid.state.data()};
  std::size_t w = 0;
  largest = 0;
  const bool wide = detail::avx512Forms();
  const bool gathers = detail::inputGathers(layout.ox, layout.oy, layout.oz);
  const auto readRow = gathers ? readPlaceRowAvx2<true> : readPlaceRowAvx2<false>;
  // (plain loads on every profile, as the unorganized pass: on the Intel host of session 19
  // 0.994-0.999 of the gathers' grid time, on Zen 4 0.94; docs/benchmark.md)
  const auto readRowWide = detail::next32Layout(layout.ox, layout.oy, layout.oz, static_cast<std::size_t>(layout.oring),
                                                layout.oring >= 0)
                               ? readPlaceRowAvx512<true>
                               : readPlaceRowAvx512<false>;
  for (std::size_t r = 0; r < R; ++r)
  {
    // (the last record's 32-bit ring read, or its 16 or 32 bytes from x, could pass the end of
    // the data: the last row's last group goes one column at a time)
    const std::size_t cols = r + 1 < R || (layout.oring < 0 && gathers) ? W : W - 1;
    const std::size_t wide_cols = wide ? cols / 16 * 16 : 0;
    const std::uint8_t* const row = view.data + r * view.row_step;
    if (wide_cols > 0) w = readRowWide(row, layout, out, r * W, wide_cols, w, ring_sum_[r], largest);
    w = readRow(row, layout, out, r * W, W, wide_cols, cols / 8 * 8, w, ring_sum_[r], largest);
    grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
  }
  grid.state.resize(n);
  tmp_index_.resize(w);
  sorted_az_.resize(w);
  return true;
#else
  (void)view;
  (void)params;
  (void)grid;
  (void)largest;
  return false;
#endif
}

}  // namespace ring_curvature
