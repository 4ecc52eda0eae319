// Builds the ring x azimuth scan grid in O(n): the input pass (grid_input.cpp), a counting sort
// by ring and an insertion sort by azimuth within each ring (ring_sort.cpp), the measured
// resolution (grid_resolution.cpp), then dual returns, the gather in grid order, links along
// rings and across them.
#include "ring_curvature/scan_grid.hpp"

#include "cloud_view_checks.hpp"
#include "compress_table.hpp"
#include "record_read.hpp"
#include "simd_clones.hpp"

#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr float kTwoPi = 6.28318530717959f;

// Grid coordinates in grid order from the input pass's float32 copies (float32 widens to double
// exactly), a gather that vectorizes on AVX2.
RC_SIMD_CLONES void gatherXyz(std::size_t m, const std::uint32_t* __restrict index, const float* __restrict px,
                              const float* __restrict py, const float* __restrict pz, const double* __restrict prange,
                              double* __restrict gx, double* __restrict gy, double* __restrict gz,
                              double* __restrict gr)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    const std::uint32_t i = index[p];
    gx[p] = px[i];
    gy[p] = py[i];
    gz[p] = pz[i];
    gr[p] = prange[i];
  }
}

// Links along a ring (b, e): one test per sample against its predecessor, in loops of their own
// that the compiler vectorizes (through the grid's vectors and with the organized / unorganized
// choice inside, it went one byte at a time).
RC_SIMD_CLONES void linkAzimuths(std::size_t b, std::size_t e, const float* __restrict az, float max_step,
                                 std::uint8_t* __restrict linked)
{
  for (std::size_t p = b + 1; p < e; ++p) linked[p] = az[p] - az[p - 1] <= max_step ? 1 : 0;
}
RC_SIMD_CLONES void linkColumns(std::size_t b, std::size_t e, const std::uint32_t* __restrict column,
                                std::uint32_t max_cols, std::uint8_t* __restrict linked)
{
  for (std::size_t p = b + 1; p < e; ++p) linked[p] = column[p] - column[p - 1] <= max_cols ? 1 : 0;
}

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

// The input indices i in [i0, n) with state[i] == Duplicate, ascending, to out; returns how many.
// Branch-free: dual-return frames make the test a coin toss per point.
std::size_t listDuplicates(const PointState* state, std::size_t i0, std::size_t n, std::uint32_t* out)
{
  std::size_t count = 0;
  for (std::size_t i = i0; i < n; ++i)
  {
    out[count] = static_cast<std::uint32_t>(i);
    count += state[i] == PointState::Duplicate ? 1 : 0;
  }
  return count;
}

#if defined(RC_SIMD_CLONES_ON)
// listDuplicates eight states at a time: their Duplicate mask picks the offsets to store from
// the compress table (compress_table.hpp), and the count moves by its popcount (one store of
// eight indices, where the plain loop made one store and one dependent count update per point;
// ~1 % of a dual-return frame). Writes up to 7 entries past the count (the caller leaves room).
// Returns the count, and in `done` the points it went through.
__attribute__((target("avx2,popcnt"))) std::size_t listDuplicatesAvx2(const PointState* state, std::size_t n,
                                                                        std::uint32_t* out, std::size_t& done)
{
  const __m128i dup = _mm_set1_epi8(static_cast<char>(PointState::Duplicate));
  std::size_t count = 0, i = 0;
  for (; i + 8 <= n; i += 8)
  {
    const __m128i s = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(state + i));
    const auto mask = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(s, dup))) & 0xFFu;
    const __m256i offsets = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompress.lane[mask]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + count),
                        _mm256_add_epi32(offsets, _mm256_set1_epi32(static_cast<int>(i))));
    count += static_cast<std::size_t>(__builtin_popcount(mask));
  }
  done = i;
  return count;
}
#endif

}  // namespace

int ScanGrid::ringOf(std::uint32_t pos) const
{
  const auto it = std::upper_bound(ring_begin.begin(), ring_begin.end(), pos);
  return static_cast<int>(it - ring_begin.begin()) - 1;
}

Status ScanGridBuilder::build(const PointCloudView& view, const Params& params, ScanGrid& grid)
{
  grid.num_rings = 0;
  grid.organized = view.organized();
  grid.ring_begin.assign(1, 0);
  grid.index.clear();
  grid.state.clear();
  grid.grid_pos.clear();
  grid.num_input = grid.num_valid = grid.num_duplicates = grid.num_second_returns = grid.num_folded = 0;
  for (auto* v : {&grid.x, &grid.y, &grid.z, &grid.range}) v->clear();
  grid.azimuth.clear();
  grid.duplicates.clear();
  grid.linked.clear();
  grid.up.clear();

  Status st = checkLayout(view, params);
  if (!st) return st;
  if (view.size() == 0) return Status::success();

  st = readPoints(view, params, grid);
  if (!st)
  {
    grid.state.clear();
    grid.grid_pos.clear();
    return st;
  }
  if (params.ring_from_elevation && !view.ring.present() && !view.organized()) assignRingsFromElevation(view, params, grid);
  if (view.organized())
    placeOrganized(view, grid);
  else
    sortRings(grid, params.duplicate_azimuth_fraction > 0.0f);
  measureResolution(params, grid);
  if (!view.organized()) removeDuplicates(params, grid);

  // Gather the structure-of-arrays grid in final order. For float32 clouds x, y, z come from
  // the input pass's float copies: 12 bytes a point, where the records are 22 (velodyne) or 48
  // (ouster) and were read a second time here; the values are the same (float32 widens to double
  // exactly). Other clouds are read from their records (float64 keeps its precision). The sorted
  // order and azimuths become the grid's by a swap (the scratch takes the grid's old buffers: no
  // copy, no allocation).
  const std::size_t m = tmp_index_.size();
  grid.index.swap(tmp_index_);
  grid.azimuth.swap(sorted_az_);
  // Both buffers of each pair take the larger capacity: otherwise they would alternate roles
  // with unequal capacities, and a large frame could meet the smaller one long after warm-up.
  tmp_index_.reserve(grid.index.capacity());
  sorted_az_.reserve(grid.azimuth.capacity());
  grid.x.resize(m);
  grid.y.resize(m);
  grid.z.resize(m);
  grid.range.resize(m);
  grid.num_valid = m;
  grid.ring_elevation.assign(static_cast<std::size_t>(grid.num_rings), 0.0f);
  grid.ring_cos.assign(static_cast<std::size_t>(grid.num_rings), 1.0f);
  double* const gx = grid.x.data();
  double* const gy = grid.y.data();
  double* const gz = grid.z.data();
  double* const gr = grid.range.data();
  const std::uint32_t* const index = grid.index.data();
  const bool fast = view.x.type == ScalarType::Float32 && view.y.type == ScalarType::Float32 &&
                    view.z.type == ScalarType::Float32;
  if (fast)
  {
    gatherXyz(m, index, px_.data(), py_.data(), pz_.data(), prange_.data(), gx, gy, gz, gr);
  }
  else
  {
    const std::size_t W = view.width;
    std::size_t row = 0;  // organized: grid order is input order, so the row only ever grows
    for (std::size_t p = 0; p < m; ++p)
    {
      const std::uint32_t i = index[p];
      const std::uint8_t* rec;
      if (view.height == 1)
      {
        rec = view.data + static_cast<std::size_t>(i) * view.point_step;
      }
      else
      {
        while (i >= (row + 1) * W) ++row;
        rec = view.data + row * view.row_step + (i - row * W) * view.point_step;
      }
      gx[p] = readCoord(rec, view.x);
      gy[p] = readCoord(rec, view.y);
      gz[p] = readCoord(rec, view.z);
      gr[p] = prange_[i];
    }
  }
  // Grid positions, and the mean elevation of each ring (for the cone's development factor
  // cos(phi)), summed in grid order.
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    double s = 0;
    for (std::uint32_t p = b; p < e; ++p)
    {
      grid.grid_pos[index[p]] = static_cast<std::int32_t>(p);
      s += gz[p] / gr[p];
    }
    const double sine = e > b ? std::clamp(s / (e - b), -1.0, 1.0) : 0.0;
    grid.ring_elevation[static_cast<std::size_t>(n)] = static_cast<float>(std::asin(sine));
    grid.ring_cos[static_cast<std::size_t>(n)] = static_cast<float>(std::sqrt(1.0 - sine * sine));
  }
  if (!view.organized()) resolveFollowers(grid);  // needs the grid positions just set
  // The Duplicate points in ascending input order (their grid_pos was set by removeDuplicates).
  grid.duplicates.clear();
  if (grid.num_duplicates > 0)
  {
    grid.duplicates.resize(grid.num_input + 8);  // (room for the vector stores' overrun)
    std::uint32_t* const dup = grid.duplicates.data();
    std::size_t count = 0, done = 0;
#if defined(RC_SIMD_CLONES_ON)
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt"))
      count = listDuplicatesAvx2(grid.state.data(), grid.num_input, dup, done);
#endif
    count += listDuplicates(grid.state.data(), done, grid.num_input, dup + count);
    grid.duplicates.resize(count);
  }
  linkRings(params, grid);
  findVerticalNeighbours(grid);
  return Status::success();
}


void ScanGridBuilder::placeOrganized(const PointCloudView& view, ScanGrid& grid)
{
  // Row = ring, column order = azimuth order: the sensor already gives the grid.
  const std::size_t R = view.height, W = view.width;
  grid.ring_begin.assign(R + 1, 0);
  // Branch-free compaction into presized arrays (NaN-padded sensors make validity a coin toss
  // per point): every point is written at w, only valid ones advance it.
  tmp_index_.resize(R * W + 1);
  sorted_az_.resize(R * W + 1);
  column_.resize(R * W + 1);
  std::uint32_t* const index = tmp_index_.data();
  float* const az = sorted_az_.data();
  std::uint32_t* const column = column_.data();
  const std::int32_t* const ring = ring_of_.data();
  std::size_t w = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    for (std::size_t c = 0; c < W; ++c)
    {
      const std::size_t i = r * W + c;
      index[w] = static_cast<std::uint32_t>(i);
      az[w] = paz_[i];
      column[w] = static_cast<std::uint32_t>(c);
      w += ring[i] >= 0 ? 1 : 0;
    }
    grid.ring_begin[r + 1] = static_cast<std::uint32_t>(w);
  }
  tmp_index_.resize(w);
  sorted_az_.resize(w);
  column_.resize(w);
}

void ScanGridBuilder::removeDuplicates(const Params& params, ScanGrid& grid)
{
  // Returns of the same firing (dual-return mode) sit at (almost) the same azimuth. An identical
  // one is a Duplicate that shares its representative's label; a different range is a second
  // return kept off the grid, so the ring stays a curve (one sample per firing).
  const float same_firing = params.duplicate_azimuth_fraction * grid.azimuth_resolution;
  const float same_range = std::max(params.range_noise, 0.005f);
  std::uint32_t w = 0;
  std::uint32_t new_begin = 0;
  std::size_t duplicates = 0, removed = 0;
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    grid.ring_begin[static_cast<std::size_t>(n)] = new_begin;
    std::int64_t rep = -1;  // input index of the current representative
    float rep_az = 0.0f;
    for (std::uint32_t p = b; p < e; ++p)
    {
      const std::uint32_t i = tmp_index_[p];
      const float az = sorted_az_[p];
      if (rep >= 0 && az - rep_az < same_firing)
      {
        // The first return of a firing stays on the grid (deterministic; both returns of a
        // dual-return firing lie on the same ray, so either continues the ring's curve).
        const std::size_t ri = static_cast<std::size_t>(rep);
        const bool same = std::fabs(prange_[i] - prange_[ri]) <= static_cast<double>(same_range);
        grid.state[i] = same ? PointState::Duplicate : PointState::SecondReturn;
        duplicates += same ? 1 : 0;  // in a register (see resolveFollowers)
        ++removed;
        grid.grid_pos[i] = static_cast<std::int32_t>(w - 1);  // the representative's grid position
        continue;
      }
      tmp_index_[w] = i;
      sorted_az_[w++] = az;
      rep = i;
      rep_az = az;
    }
    new_begin = w;
  }
  grid.num_duplicates += duplicates;
  grid.num_second_returns += removed - duplicates;
  grid.ring_begin[static_cast<std::size_t>(grid.num_rings)] = w;
  tmp_index_.resize(w);
  sorted_az_.resize(w);
}

void ScanGridBuilder::linkRings(const Params& params, ScanGrid& grid)
{
  const std::size_t m = grid.size();
  grid.linked.resize(m);  // every entry is written below: each ring's first by its seam test
  grid.ring_closed.assign(static_cast<std::size_t>(grid.num_rings), 0);
  const float max_step = (static_cast<float>(params.max_gap_samples) + 1.5f) * grid.azimuth_resolution;
  const std::uint32_t max_cols = static_cast<std::uint32_t>(params.max_gap_samples) + 1;
  std::uint8_t* const linked = grid.linked.data();
  for (int n = 0; n < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    if (e - b < 2)
    {
      if (e > b) linked[b] = 0;
      continue;
    }
    if (grid.organized)
      linkColumns(b, e, column_.data(), max_cols, linked);
    else
      linkAzimuths(b, e, grid.azimuth.data(), max_step, linked);
    // The seam: the last sample connects to the first when the ring covers the full circle.
    bool closed;
    if (grid.organized)
    {
      const float sweep = static_cast<float>(grid.num_input / static_cast<std::size_t>(grid.num_rings)) * grid.azimuth_resolution;
      const std::uint32_t width = static_cast<std::uint32_t>(grid.num_input / static_cast<std::size_t>(grid.num_rings));
      closed = std::fabs(sweep - kTwoPi) < 0.05f * kTwoPi && column_[b] + width - column_[e - 1] <= max_cols;
    }
    else
    {
      closed = grid.azimuth[b] + kTwoPi - grid.azimuth[e - 1] <= max_step;
    }
    closed = closed && e - b >= 3;
    grid.ring_closed[static_cast<std::size_t>(n)] = closed ? 1 : 0;
    linked[b] = closed ? 1 : 0;
  }
}

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
