// The grid's input pass: every input record read once into per-point scratch (range, validity,
// ring, azimuth), with fast paths for the common layouts, and rings found from elevation when a
// cloud has no ring field.
#include "ring_curvature/scan_grid.hpp"

#include "angles.hpp"
#include "input_avx2.hpp"
#include "input_avx512.hpp"
#include "ring_curvature/prefetch.hpp"
#include "record_read.hpp"
#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace ring_curvature
{

namespace
{

// The input pass's entries for point i: its range decides validity (NaN and inf fail both
// comparisons); the entries of invalid points are written too (x / y / z then hold values
// nothing reads). Shared by the vectorized reader below and the generic loop of readPoints.
// x, y, z as float32 feed the azimuths and, for float32 clouds, the grid's coordinates (see
// ScanGridBuilder::build).
struct PointEntries
{
  double* range;
  float* x;
  float* y;
  float* z;
  std::int32_t* ring;
  PointState* state;
  std::int32_t* grid_pos;
};
inline void storePoint(const PointEntries& out, std::size_t i, double x, double y, double z, std::int32_t ring,
                       double rmin, double rmax)
{
  const double range = std::sqrt(x * x + y * y + z * z);
  const bool valid = (range >= rmin) & (range <= rmax);
  out.range[i] = range;
  out.x[i] = static_cast<float>(x);
  out.y[i] = static_cast<float>(y);
  out.z[i] = static_cast<float>(z);
  out.ring[i] = valid ? ring : -1;
  out.state[i] = valid ? PointState::OnGrid : PointState::Invalid;
  out.grid_pos[i] = -1;
}

// The common layouts: float32 x, y, z at fixed offsets of `step`-byte records, and either a
// uint16 ring field (velodyne, unorganized ouster; `has_ring`) or one ring for all (a row of an
// organized cloud; `fixed_ring`). One loop without branches, early exits or per-point dispatch
// on types, which the compiler vectorizes with gathers on AVX2 (RC_SIMD_CLONES). Returns the
// largest ring field read, so the caller
// can reject the frame after the loop. (Without a ring field, `oring` only has to lie inside the
// record: the value read there is not used.)
RC_SIMD_CLONES std::uint32_t readXyzRecords(const std::uint8_t* __restrict data, std::size_t n, std::size_t step,
                                            std::size_t ox, std::size_t oy, std::size_t oz, std::size_t oring,
                                            bool has_ring, std::int32_t fixed_ring, double rmin, double rmax,
                                            double* __restrict range_out, float* __restrict px, float* __restrict py,
                                            float* __restrict pz, std::int32_t* __restrict ring_out,
                                            PointState* __restrict state, std::int32_t* __restrict grid_pos)
{
  const PointEntries out{range_out, px, py, pz, ring_out, state, grid_pos};
  std::uint32_t max_read = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t* const rec = data + i * step;
    const float fx = readFloat32(rec + ox), fy = readFloat32(rec + oy), fz = readFloat32(rec + oz);
    std::uint16_t r16;
    std::memcpy(&r16, rec + oring, sizeof r16);
    max_read = has_ring ? std::max<std::uint32_t>(max_read, r16) : max_read;
    const std::int32_t ring = has_ring ? static_cast<std::int32_t>(r16) : fixed_ring;
    storePoint(out, i, fx, fy, fz, ring, rmin, rmax);
  }
  return max_read;
}

// Azimuths of points at once (fastAtan2 is branch-free: 4 or 8 at a time): the generic input
// loop's, and those of the points the AVX2 input pass leaves (see readRecords).
RC_SIMD_CLONES void azimuths(std::size_t n, const float* __restrict x, const float* __restrict y,
                               float* __restrict azimuth)
{
  for (std::size_t i = 0; i < n; ++i) azimuth[i] = fastAtan2(y[i], x[i]);
}

#if defined(RC_SIMD_CLONES_ON)
// readXyzRecords eight points at a time, written with AVX2 intrinsics: each field is one gather
// and each output one store. The compiler's vectorization of the loop above worked sixteen points
// at a time, loading every field with a single-lane insert and spilling its vectors to the stack
// (~24 instructions a point, where these are ~5). The same operations lane by lane: x, y, z
// widened to double, range = sqrt((x x + y y) + z z), valid = range >= rmin and range <= rmax
// (NaN fails both). The float copies are the fields' bits as read (for a valid point that is
// the float of its double; an invalid one's are never read). The 32 bits at the ring's offset
// are gathered and masked to 16, so the last group whose read could pass the end of the data
// (the last point's) is left to the loop above. Returns the points done and updates max_read.
// kGathers false (CPUs with slow gathers, cpu_tuning.hpp; needs oy = ox + 4, oz = ox + 8): the
// same bytes read with plain loads instead (input_avx2.hpp), x, y, z as 16 bytes a record from
// its x; those stay inside the data for the same reason (16 <= step + 4 bytes past a record's x,
// and the last record is left out). kNext32 (a ring field 16 bytes after x, velodyne's XYZIRT):
// 32 bytes a record from its x, which hold the ring too (32 <= step + 14, as the ring's two bytes
// end 18 bytes past x or more).
template <bool kGathers, bool kNext32 = false>
__attribute__((target("avx2"))) std::size_t readXyzRecordsAvx2(
    const std::uint8_t* data, std::size_t n, std::size_t step, std::size_t ox, std::size_t oy, std::size_t oz,
    std::size_t oring, bool has_ring, std::int32_t fixed_ring, double rmin, double rmax, double* range_out, float* px,
    float* py, float* pz, float* paz, std::int32_t* ring_out, PointState* state, std::int32_t* grid_pos,
    std::uint32_t& max_read)
{
  // every gather offset of a group (7 steps and a field offset) must fit an int32
  if ((kGathers && step > (1u << 26)) || n < 9) return 0;
  const int st = static_cast<int>(step);
  const __m256i lanes = _mm256_setr_epi32(0, st, 2 * st, 3 * st, 4 * st, 5 * st, 6 * st, 7 * st);
  const __m256i vx = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(ox)));
  const __m256i vy = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(oy)));
  const __m256i vz = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(oz)));
  const __m256i vr = _mm256_add_epi32(lanes, _mm256_set1_epi32(static_cast<int>(oring)));
  const __m256i low16 = _mm256_set1_epi32(0xFFFF), fixed = _mm256_set1_epi32(fixed_ring);
  const __m256i none = _mm256_set1_epi32(-1), one = _mm256_set1_epi32(static_cast<int>(PointState::OnGrid));
  const __m256d lo = _mm256_set1_pd(rmin), hi = _mm256_set1_pd(rmax);
  __m256i largest = _mm256_setzero_si256();
  std::size_t i = 0;
  for (; i + 8 < n; i += 8)  // (not the last point: its ring read could pass the end)
  {
    // Eight store streams, on lines last written a frame ago (ring_curvature/prefetch.hpp): each stream's
    // line kWriteAhead points ahead (a 32-byte stream asks for each line twice: a test would
    // cost as much), the one-byte states' every eighth group.
    {
      using detail::prefetchForWrite;
      constexpr std::size_t A = detail::kWriteAhead;
      prefetchForWrite(range_out, (i + A) * sizeof(double));
      prefetchForWrite(px, (i + A) * sizeof(float));
      prefetchForWrite(py, (i + A) * sizeof(float));
      prefetchForWrite(pz, (i + A) * sizeof(float));
      prefetchForWrite(paz, (i + A) * sizeof(float));
      prefetchForWrite(ring_out, (i + A) * sizeof(std::int32_t));
      prefetchForWrite(grid_pos, (i + A) * sizeof(std::int32_t));
      if ((i & 63) == 0) prefetchForWrite(state, i + A);
      detail::prefetchRecords(data, i + detail::kRecordsAhead, 8, step, ox);  // (see the AVX-512 form)
    }
    const auto* const base = reinterpret_cast<const float*>(data + i * step);
    __m256 x, y, z;
    __m256i bits = none;  // (kNext32: the ring's 32 bits)
    if constexpr (kGathers)
    {
      x = _mm256_i32gather_ps(base, vx, 1);
      y = _mm256_i32gather_ps(base, vy, 1);
      z = _mm256_i32gather_ps(base, vz, 1);
    }
    else if constexpr (kNext32)
      detail::loadXyzNext32Avx2(data + i * step + ox, step, x, y, z, bits);
    else
      detail::loadXyzAvx2(data + i * step + ox, step, x, y, z);
    __m256d r0, r1;
    detail::rangesAvx2(x, y, z, r0, r1);
    _mm256_storeu_pd(range_out + i, r0);
    _mm256_storeu_pd(range_out + i + 4, r1);
    _mm256_storeu_ps(px + i, x);
    _mm256_storeu_ps(py + i, y);
    _mm256_storeu_ps(pz + i, z);
    _mm256_storeu_ps(paz + i, detail::fastAtan2Avx2(y, x));
    const __m256i valid = detail::validAvx2(r0, r1, lo, hi);
    __m256i ring = fixed;
    if (has_ring)
    {
      if constexpr (kGathers)
        ring = _mm256_and_si256(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), vr, 1), low16);
      else if constexpr (kNext32)
        ring = _mm256_and_si256(bits, low16);
      else
        ring = _mm256_and_si256(detail::load32Avx2(data + i * step + oring, step), low16);
      largest = _mm256_max_epu32(largest, ring);
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(ring_out + i), _mm256_blendv_epi8(none, ring, valid));
    const __m256i s = _mm256_and_si256(valid, one);  // OnGrid (1) or Invalid (0) per lane
    const __m128i s16 = _mm_packs_epi32(_mm256_castsi256_si128(s), _mm256_extracti128_si256(s, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(state + i), _mm_packs_epi16(s16, s16));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(grid_pos + i), none);
  }
  alignas(32) std::uint32_t l[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(l), largest);
  for (const std::uint32_t v : l) max_read = std::max(max_read, v);
  return i;
}
#endif

#if defined(RC_SIMD_CLONES_ON)
RC_AVX512_BEGIN  // (simd_clones.hpp: GCC 12's false -Wmaybe-uninitialized)
// readXyzRecordsAvx2 sixteen points at a time with AVX-512F: the same operations lane by lane
// (input_avx512.hpp). Half the instructions a point: the azimuth polynomial, the range and the
// stores were the pass's cost more than its gathers. Same contract as readXyzRecordsAvx2 (the
// last point is left to the loops after it). kNext32 (x, y, z one run of floats and a ring field
// 16 to 30 bytes past x, not across a 4-byte word of the run: velodyne's XYZIRT): each record's
// 32 bytes from its x instead of four gathers (loadXyzNext32Avx512), the ring's 16 bits shifted
// out of their word; those loads stay inside the data (the ring's two bytes end 18 bytes past x
// or more, so 32 <= step + 14, and the last record is left out).
template <bool kNext32>
__attribute__((target("avx512f"))) std::size_t readXyzRecordsAvx512(
    const std::uint8_t* data, std::size_t n, std::size_t step, std::size_t ox, std::size_t oy, std::size_t oz,
    std::size_t oring, bool has_ring, std::int32_t fixed_ring, double rmin, double rmax, double* range_out, float* px,
    float* py, float* pz, float* paz, std::int32_t* ring_out, PointState* state, std::int32_t* grid_pos,
    std::uint32_t& max_read)
{
  // every gather offset of a group (15 steps and a field offset) must fit an int32
  if (step > (1u << 26) || n < 17) return 0;
  const __m512i lanes = _mm512_mullo_epi32(_mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0),
                                           _mm512_set1_epi32(static_cast<int>(step)));
  const __m512i vx = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(ox)));
  const __m512i vy = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(oy)));
  const __m512i vz = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(oz)));
  const __m512i vr = _mm512_add_epi32(lanes, _mm512_set1_epi32(static_cast<int>(oring)));
  const __m512i low16 = _mm512_set1_epi32(0xFFFF), fixed = _mm512_set1_epi32(fixed_ring);
  const __m512i none = _mm512_set1_epi32(-1), one = _mm512_set1_epi32(static_cast<int>(PointState::OnGrid));
  const __m512d lo = _mm512_set1_pd(rmin), hi = _mm512_set1_pd(rmax);
  const int ring_word = static_cast<int>((oring - ox) / 4);  // (kNext32)
  const __m512i pick = detail::next32PickAvx512(ring_word);
  const __m128i ring_shift = _mm_cvtsi32_si128(static_cast<int>((oring - ox) % 4 * 8));
  __m512i largest = _mm512_setzero_si512();
  std::size_t i = 0;
  for (; i + 16 < n; i += 16)  // (not the last point: its ring read could pass the end)
  {
    {
      // one line of each float stream a group, two of the ranges, a quarter of the states'
      using detail::prefetchForWrite;
      constexpr std::size_t A = detail::kWriteAhead;
      prefetchForWrite(range_out, (i + A) * sizeof(double));
      prefetchForWrite(range_out, (i + A + 8) * sizeof(double));
      prefetchForWrite(px, (i + A) * sizeof(float));
      prefetchForWrite(py, (i + A) * sizeof(float));
      prefetchForWrite(pz, (i + A) * sizeof(float));
      prefetchForWrite(paz, (i + A) * sizeof(float));
      prefetchForWrite(ring_out, (i + A) * sizeof(std::int32_t));
      prefetchForWrite(grid_pos, (i + A) * sizeof(std::int32_t));
      if ((i & 63) == 0) prefetchForWrite(state, i + A);
      // the records a few kilobytes ahead: the gathers below waited for them (perf)
      detail::prefetchRecords(data, i + detail::kRecordsAhead, 16, step, ox);
    }
    const auto* const base = reinterpret_cast<const float*>(data + i * step);
    __m512 x, y, z;
    __m512i bits = none;  // (kNext32: the 32 bits holding the ring)
    if constexpr (kNext32)
      detail::loadXyzNext32Avx512(data + i * step + ox, step, pick, x, y, z, bits);
    else
    {
      x = _mm512_i32gather_ps(vx, base, 1);
      y = _mm512_i32gather_ps(vy, base, 1);
      z = _mm512_i32gather_ps(vz, base, 1);
    }
    const __m512d r0 = detail::range8Avx512(_mm512_castps512_ps256(x), _mm512_castps512_ps256(y),
                                            _mm512_castps512_ps256(z));
    const __m512d r1 = detail::range8Avx512(
        _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1)),
        _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(y), 1)),
        _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(z), 1)));
    _mm512_storeu_pd(range_out + i, r0);
    _mm512_storeu_pd(range_out + i + 8, r1);
    _mm512_storeu_ps(px + i, x);
    _mm512_storeu_ps(py + i, y);
    _mm512_storeu_ps(pz + i, z);
    _mm512_storeu_ps(paz + i, detail::fastAtan2Avx512(y, x));
    const auto valid = static_cast<__mmask16>(detail::valid8Avx512(r0, lo, hi) |
                                              (static_cast<unsigned>(detail::valid8Avx512(r1, lo, hi)) << 8));
    __m512i ring = fixed;
    if (has_ring)
    {
      if constexpr (kNext32)
        ring = _mm512_and_si512(_mm512_srl_epi32(bits, ring_shift), low16);
      else
        ring = _mm512_and_si512(_mm512_i32gather_epi32(vr, base, 1), low16);
      largest = _mm512_max_epu32(largest, ring);
    }
    _mm512_storeu_si512(ring_out + i, _mm512_mask_blend_epi32(valid, none, ring));
    // OnGrid (1) or Invalid (0) per lane, narrowed to bytes
    _mm_storeu_si128(reinterpret_cast<__m128i*>(state + i), _mm512_cvtepi32_epi8(_mm512_maskz_mov_epi32(valid, one)));
    _mm512_storeu_si512(grid_pos + i, none);
  }
  max_read = std::max(max_read, _mm512_reduce_max_epu32(largest));
  return i;
}
RC_AVX512_END
#endif

// The input pass over records [0, n) (see readXyzRecords): with AVX-512 sixteen at a time, with
// AVX2 eight at a time, the rest one at a time.
std::uint32_t readRecords(const std::uint8_t* data, std::size_t n, std::size_t step, std::size_t ox,
                          std::size_t oy, std::size_t oz, std::size_t oring, bool has_ring, std::int32_t fixed_ring,
                          double rmin, double rmax, double* range_out, float* px, float* py, float* pz, float* paz,
                          std::int32_t* ring_out, PointState* state, std::int32_t* grid_pos)
{
  std::uint32_t max_read = 0;
  std::size_t done = 0;
#if defined(RC_SIMD_CLONES_ON)
  if (detail::avx512Forms())
  {
    // (plain loads on every profile: measured faster than the gathers on Sapphire Rapids)
    const auto read = detail::next32Layout(ox, oy, oz, oring, has_ring) ? readXyzRecordsAvx512<true>
                                                                         : readXyzRecordsAvx512<false>;
    done = read(data, n, step, ox, oy, oz, oring, has_ring, fixed_ring, rmin, rmax, range_out, px, py, pz, paz,
                ring_out, state, grid_pos, max_read);
  }
  if (__builtin_cpu_supports("avx2"))
  {
    const std::size_t o = done * step;
    // (plain loads where the gathers are slow and x, y, z are one run of floats, cpu_tuning.hpp)
    const auto read = detail::inputGathers(ox, oy, oz) ? readXyzRecordsAvx2<true>
                      : has_ring && oring == ox + 16   ? readXyzRecordsAvx2<false, true>
                                                       : readXyzRecordsAvx2<false>;
    done += read(
        data + o, n - done, step, ox, oy, oz, oring, has_ring, fixed_ring, rmin, rmax, range_out + done, px + done,
        py + done, pz + done, paz + done, ring_out + done, state + done, grid_pos + done, max_read);
  }
#endif
  const std::size_t o = done * step;
  max_read = std::max(max_read, readXyzRecords(data + o, n - done, step, ox, oy, oz, oring, has_ring, fixed_ring, rmin,
                                               rmax, range_out + done, px + done, py + done, pz + done,
                                               ring_out + done, state + done, grid_pos + done));
  azimuths(n - done, px + done, py + done, paz + done);
  return max_read;
}

}  // namespace

Status ScanGridBuilder::readPoints(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  const std::size_t n = view.size();
  grid.num_input = n;
  placed_ = false;
  // Every entry of these is written below (no fill first: one pass over the frame instead of two).
  grid.state.resize(n);
  grid.grid_pos.resize(n);
  ring_of_.resize(n);
  prange_.resize(n + 1);  // [n]: the ring fold's sentinel range (ring_sort.cpp)
  paz_.resize(n);
  px_.resize(n);
  py_.resize(n);
  pz_.resize(n);
  const double rmin = params.min_range, rmax = params.max_range;
  const auto ringError = [&](std::size_t i, std::int64_t r) {
    std::ostringstream s;
    s << "point " << i << " has ring " << r << ", outside [0, max_rings = " << params.max_rings << ")";
    return Status::error(s.str());
  };
  // The first point whose uint16 ring field is max_rings or more (one is known to be), for the
  // message: the vectorized input passes only track the largest value read.
  const auto firstRing16Error = [&]() {
    std::size_t i = 0;
    std::uint16_t r16 = 0;
    for (; i < n; ++i)
    {
      std::memcpy(&r16, view.record(i) + view.ring.offset, sizeof r16);
      if (r16 >= params.max_rings) break;
    }
    return ringError(i, r16);
  };
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  if (fast && !view.organized() && view.ring.present() && view.ring.type == ScalarType::UInt16)
  {
    const std::uint32_t max_read = readRecords(
        view.data, n, view.point_step, static_cast<std::size_t>(view.x.offset), static_cast<std::size_t>(view.y.offset),
        static_cast<std::size_t>(view.z.offset), static_cast<std::size_t>(view.ring.offset), true, 0, rmin, rmax,
        prange_.data(), px_.data(), py_.data(), pz_.data(), paz_.data(), ring_of_.data(), grid.state.data(),
        grid.grid_pos.data());
    if (max_read >= static_cast<std::uint32_t>(params.max_rings)) return firstRing16Error();
  }
  else if (fast && view.organized())
  {
    std::uint32_t largest_field = 0;
    if (readOrganized(view, params, grid, largest_field))
    {
      placed_ = true;
      return largest_field < static_cast<std::uint32_t>(params.max_rings) ? Status::success() : firstRing16Error();
    }
    // organized float32 (ouster): row by row, the row is the ring; a ring field is only checked
    for (std::uint32_t row = 0; row < view.height; ++row)
    {
      const std::uint8_t* const data = view.data + static_cast<std::size_t>(row) * view.row_step;
      const std::size_t i0 = static_cast<std::size_t>(row) * view.width;
      readRecords(data, view.width, view.point_step, static_cast<std::size_t>(view.x.offset),
                  static_cast<std::size_t>(view.y.offset), static_cast<std::size_t>(view.z.offset),
                  static_cast<std::size_t>(view.x.offset), false, static_cast<std::int32_t>(row), rmin, rmax,
                  prange_.data() + i0, px_.data() + i0, py_.data() + i0, pz_.data() + i0, paz_.data() + i0,
                  ring_of_.data() + i0, grid.state.data() + i0, grid.grid_pos.data() + i0);
      if (!view.ring.present()) continue;
      const std::uint8_t* rec = data + view.ring.offset;
      if (view.ring.type == ScalarType::UInt16)  // ouster: read inline, the largest value checked after
      {
        std::uint32_t largest = 0;
        for (std::uint32_t col = 0; col < view.width; ++col, rec += view.point_step)
        {
          std::uint16_t r16;
          std::memcpy(&r16, rec, sizeof r16);
          largest = std::max<std::uint32_t>(largest, r16);
        }
        if (largest < static_cast<std::uint32_t>(params.max_rings)) continue;
        rec = data + view.ring.offset;  // out of range somewhere: find the first, for the message
      }
      for (std::uint32_t col = 0; col < view.width; ++col, rec += view.point_step)
      {
        const std::int64_t r = readInteger(rec, view.ring.type);
        if (r < 0 || r >= params.max_rings) return ringError(i0 + col, r);
      }
    }
  }
  else
  {
    const PointEntries entries{prange_.data(), px_.data(), py_.data(), pz_.data(),
                               ring_of_.data(), grid.state.data(), grid.grid_pos.data()};
    for (std::uint32_t row = 0; row < view.height; ++row)
    {
      const std::uint8_t* rec = view.data + static_cast<std::size_t>(row) * view.row_step;
      for (std::uint32_t col = 0; col < view.width; ++col, rec += view.point_step)
      {
        const std::size_t i = static_cast<std::size_t>(row) * view.width + col;
        int ring = static_cast<int>(row);
        if (view.ring.present())
        {
          const std::int64_t r = readInteger(rec + view.ring.offset, view.ring.type);
          if (r < 0 || r >= params.max_rings) return ringError(i, r);
          if (!view.organized()) ring = static_cast<int>(r);  // organized: the row is the ring
        }
        storePoint(entries, i, readCoord(rec, view.x), readCoord(rec, view.y), readCoord(rec, view.z), ring, rmin,
                   rmax);
      }
    }
    azimuths(n, px_.data(), py_.data(), paz_.data());
  }
  // Points per ring ([0]: invalid ones), for the counting sort, in a pass of its own: the
  // increments would keep the loops above from vectorizing.
  // Four interleaved tallies, summed after: rings that arrive one after another (KITTI's, an
  // organized cloud's) would otherwise chain every increment to the store of the one before.
  const std::size_t slots = static_cast<std::size_t>(params.max_rings) + 1;
  ring_count_.assign(4 * slots, 0);
  {
    std::uint32_t* const count = ring_count_.data() + 1;  // ring -1 (invalid) counts at [0]
    const std::int32_t* const ring = ring_of_.data();
    const auto four = [count, ring, slots](std::size_t i) {
      ++count[ring[i]];
      ++count[slots + static_cast<std::size_t>(ring[i + 1])];
      ++count[2 * slots + static_cast<std::size_t>(ring[i + 2])];
      ++count[3 * slots + static_cast<std::size_t>(ring[i + 3])];
    };
    // Sixteen points of one ring (most blocks where rings come one after another) count in one
    // addition: a comparison that vectorizes, where the increments took 2.4 cycles a point.
    // Only where the first points come in runs: interleaved rings (velodyne firing order) would
    // pay for the comparison in every block.
    std::size_t changes = 0;
    const std::size_t probe = std::min<std::size_t>(n, 256);
    for (std::size_t j = 1; j < probe; ++j) changes += ring[j] != ring[j - 1] ? 1 : 0;
    std::size_t i = 0;
    for (; changes < probe / 8 && i + 16 <= n; i += 16)
    {
      const std::int32_t r0 = ring[i];
      int same = 1;
      for (std::size_t j = 1; j < 16; ++j) same &= ring[i + j] == r0 ? 1 : 0;
      if (same != 0)
      {
        count[r0] += 16;
        continue;
      }
      for (std::size_t j = i; j < i + 16; j += 4) four(j);
    }
    for (; i + 4 <= n; i += 4) four(i);
    for (; i < n; ++i) ++count[ring[i]];
    for (std::size_t r = 0; r < slots; ++r)
      ring_count_[r] += ring_count_[slots + r] + ring_count_[2 * slots + r] + ring_count_[3 * slots + r];
  }
  int max_ring = -1;
  for (int r = params.max_rings - 1; r >= 0 && max_ring < 0; --r)
    if (ring_count_[static_cast<std::size_t>(r) + 1] > 0) max_ring = r;
  grid.num_rings = view.organized() ? static_cast<int>(view.height) : max_ring + 1;
  return Status::success();
}

void ScanGridBuilder::assignRingsFromElevation(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  // Histogram of elevation at 0.05 deg; runs of occupied bins (a beam's spread) become rings,
  // numbered from the lowest elevation up (the velodyne convention).
  constexpr int kBins = 3600;
  constexpr float kBinRad = kPi / kBins;
  const std::size_t n = grid.num_input;
  counts_.assign(kBins, 0);
  tmp_f_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (ring_of_[i] < 0) continue;
    const std::uint8_t* rec = view.record(i);  // unorganized here: no per-point division cost
    const double x = readCoord(rec, view.x), y = readCoord(rec, view.y), z = readCoord(rec, view.z);
    const float horiz = static_cast<float>(std::sqrt(x * x + y * y));
    const float el = fastAtan2(static_cast<float>(z), horiz);
    tmp_f_[i] = el;
    const int b = std::clamp(static_cast<int>((el + kPi / 2) / kBinRad), 0, kBins - 1);
    ++counts_[static_cast<std::size_t>(b)];
  }
  bin_start_.assign(kBins, 0);  // ring id of each bin
  int ring = -1;
  int last_occupied = -10;
  for (int b = 0; b < kBins; ++b)
  {
    if (counts_[static_cast<std::size_t>(b)] == 0) continue;
    if (b - last_occupied > 2) ++ring;  // a gap of two empty bins (0.1 deg) separates beams
    last_occupied = b;
    bin_start_[static_cast<std::size_t>(b)] = static_cast<std::uint32_t>(ring);
  }
  const int num = std::min(ring + 1, params.max_rings);
  std::fill(ring_count_.begin() + 1, ring_count_.end(), 0u);  // recounted for the new rings
  for (std::size_t i = 0; i < n; ++i)
  {
    if (ring_of_[i] < 0) continue;
    const int b = std::clamp(static_cast<int>((tmp_f_[i] + kPi / 2) / kBinRad), 0, kBins - 1);
    ring_of_[i] = std::min(static_cast<int>(bin_start_[static_cast<std::size_t>(b)]), num - 1);
    ++ring_count_[static_cast<std::size_t>(ring_of_[i]) + 1];
  }
  grid.num_rings = std::max(num, 0);
}

}  // namespace ring_curvature
