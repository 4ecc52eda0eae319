// Orders the valid points of each ring by azimuth in O(n): a counting sort by ring, then per
// ring the sort of ring_order.cpp. Identical dual returns are folded on the way and given their
// twin's verdict afterwards.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"
#include "common/float_bits.hpp"
#include "grid/sort_keys.hpp"
#include "ring_curvature/prefetch.hpp"

#include "common/angles.hpp"
#include "common/grow.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cstring>
#include <type_traits>

namespace ring_curvature
{

using detail::keyAzimuth;
using detail::keyIndex;
using detail::sortKey;

namespace
{

// How often the ring changes between consecutive points (a 32-bit count: indices are 32-bit).
RC_SIMD_CLONES std::size_t ringChanges(const std::int32_t* __restrict ring, std::size_t n)
{
  std::uint32_t changes = 0;
  for (std::size_t i = 1; i < n; ++i) changes += ring[i] != ring[i - 1] ? 1u : 0u;
  return changes;
}

// The sort keys of points [i0, i0 + len) from their azimuths az[0, len).
RC_SIMD_CLONES void sortKeys(const float* __restrict az, std::size_t i0, std::size_t len, std::uint64_t* __restrict key)
{
  for (std::size_t j = 0; j < len; ++j) key[j] = sortKey(az[j], i0 + j);
}

// The sorted keys split into the input indices and the azimuths.
RC_SIMD_CLONES void splitKeys(std::size_t m, const std::uint64_t* __restrict keys, std::uint32_t* __restrict index,
                              float* __restrict az)
{
  for (std::size_t p = 0; p < m; ++p)
  {
    index[p] = keyIndex(keys[p]);
    az[p] = keyAzimuth(keys[p]);
  }
}

// Folding is only a shortcut (removeDuplicates gives an unfolded point the same verdict), so a
// frame whose first kFoldProbe points fold nothing (single return) skips the test for the rest.
constexpr std::size_t kFoldProbe = 4096;
}  // namespace

void ScanGridBuilder::sortRings(ScanGrid& grid, bool fold_identical)
{
  const std::size_t n = grid.num_input;
  const std::size_t R = static_cast<std::size_t>(grid.num_rings);
  // 1) counting sort by ring (stable: keeps firing order), carrying each point's sort key so the
  //    ring sorts compare keys instead of reading azimuths through scattered input indices.
  grid.ring_begin.assign(R + 1, 0);
  for (std::size_t r = 0; r < R; ++r) grid.ring_begin[r + 1] = grid.ring_begin[r] + ring_count_[r + 1];
  keys_tmp_.resize(grid.ring_begin[R]);
  bin_start_.resize(R + 1);
  for (std::size_t r = 0; r < R; ++r) bin_start_[r] = grid.ring_begin[r];
  //    It also folds identical dual returns (azimuth and range of one of the two points before in
  //    the ring): kept off the sort, they get their twin's state and grid position, removeDuplicates'
  //    verdict exactly (same firing, never a representative, same range). Needs same_firing > 0.
  follower_runs_.resize(2 * R + 2);
  std::size_t runs = 0;
  prange_[n] = -1.0;  // no point's range: foldRing's start value (readPoints leaves room for it)
  growTo(followers_, n + 1);  // (foldRing writes one entry past the count)
  std::size_t num_followers = 0;
  unfolded_largest_ = 0;
  for (std::size_t r = 0; r < R; ++r) unfolded_largest_ = std::max(unfolded_largest_, ring_count_[r + 1]);
  const std::int32_t* const ring_of = ring_of_.data();
  // Rings one after another (KITTI, unorganized ouster) fold as they come, state in registers;
  // rings interleaved point by point (velodyne) are scattered first, then folded ring by ring.
  if (ringChanges(ring_of, n) > n / 8)
    runs = foldScattered(grid, fold_identical, num_followers);
  else
    placeInOrder(grid, fold_identical, num_followers);
  num_followers_ = num_followers;
  if (runs == 0 && num_followers > 0)  // (rings one after another: one run, in input order)
  {
    follower_runs_[0] = 0;
    follower_runs_[1] = static_cast<std::uint32_t>(num_followers);
    runs = 1;
  }
  num_follower_runs_ = runs;
  sortEachRing(grid);
}

// Rings interleaved point by point; returns the number of follower runs in follower_runs_.
std::size_t ScanGridBuilder::foldScattered(ScanGrid& grid, bool fold_identical, std::size_t& num_followers)
{
  const std::size_t n = grid.num_input;
  const std::size_t R = static_cast<std::size_t>(grid.num_rings);
  std::uint32_t* const next = bin_start_.data();
  std::uint64_t* const unsorted = keys_tmp_.data();
  const double* const prange = prange_.data();
  Follower* const followers = followers_.data();
  std::size_t runs = 0;
  // Folded after the scatter: each ring's keys are then contiguous, in firing order, and the fold
  // keeps its state in registers. If the first kFoldProbe keys fold nothing, the rest stay as is.
  scatterInterleaved(0, n);
  if (fold_identical)
  {
    std::size_t tested = 0;
    for (std::size_t r = 0; r < R && (num_followers > 0 || tested < kFoldProbe); ++r)
    {
      const std::uint32_t b = grid.ring_begin[r], k = next[r] - b;
      const auto first = static_cast<std::uint32_t>(num_followers);
      next[r] = b + foldRing(unsorted + b, k, n, prange, followers, num_followers);
      tested += k;
      if (num_followers > first)  // the ring's followers, for resolveFollowers
      {
        follower_runs_[2 * runs] = first;
        follower_runs_[2 * runs++ + 1] = static_cast<std::uint32_t>(num_followers);
      }
    }
  }
  return runs;
}

// Rings one after another: each point placed (and folded) as it comes, its ring's state in registers.
void ScanGridBuilder::placeInOrder(ScanGrid& grid, bool fold_identical, std::size_t& num_followers)
{
  const std::size_t n = grid.num_input;
  const std::size_t R = static_cast<std::size_t>(grid.num_rings);
  std::uint32_t* const next = bin_start_.data();
  std::uint64_t* const unsorted = keys_tmp_.data();
  const std::int32_t* const ring_of = ring_of_.data();
  const float* const paz = paz_.data();
  const double* const prange = prange_.data();
  Follower* const followers = followers_.data();
  // One key into its ring (`f`, `nx`: its fold state and next slot; `fold`: whether to fold).
  // Captures by value but the count: through references they would be reloaded after every store.
  const auto place = [prange, followers, unsorted, &num_followers](std::uint64_t key, RingFold& f, std::uint32_t& nx,
                                                                   auto fold) {
    const auto az_key = static_cast<std::uint32_t>(key >> 32);
    const std::uint32_t i = keyIndex(key);
    if constexpr (decltype(fold)::value)
    {
      // Compared as bits, which for these values is the float comparison (equal azimuths have equal
      // keys, -0 included; valid ranges are positive and finite; the -1 start matches none).
      std::uint64_t range;
      std::memcpy(&range, &prange[i], sizeof range);
      const bool same1 = (az_key == f.az1) & (range == f.r1), same2 = (az_key == f.az2) & (range == f.r2);
      if (same1 | same2)
      {
        followers[num_followers++] = {i, same1 ? f.i1 : f.i2};
        return;
      }
      f.az2 = f.az1;
      f.r2 = f.r1;
      f.i2 = f.i1;
      f.az1 = az_key;
      f.r1 = range;
      f.i1 = i;
    }
    unsorted[nx++] = key;
  };
  ring_fold_.assign(R, RingFold{});  // each ring's state while another ring's points come
  RingFold* const fold = ring_fold_.data();
  std::int32_t cur = -1;
  RingFold f{};
  std::uint32_t nx = 0;
  // Points [from, to) in input order, folding or not.
  const auto run = [&](std::size_t from, std::size_t to, auto folding) {
    for (std::size_t i = from; i < to; ++i)
    {
      const std::int32_t r = ring_of[i];
      if (r < 0) continue;
      if (r != cur)
      {
        if (cur >= 0)
        {
          fold[cur] = f;
          next[cur] = nx;
        }
        cur = r;
        f = fold[r];
        nx = next[r];
      }
      place(sortKey(paz[i], i), f, nx, folding);
    }
  };
  const std::size_t probe = fold_identical ? std::min(n, kFoldProbe) : 0;
  run(0, probe, std::true_type{});
  if (num_followers > 0)
    run(probe, n, std::true_type{});
  else
    run(probe, n, std::false_type{});
  if (cur >= 0)
  {
    fold[cur] = f;
    next[cur] = nx;
  }
}

// 2) Per ring, order the keys: (azimuth, input index) is a strict total order, so the result
// depends neither on arrival order nor on which sort finishes the ring.
void ScanGridBuilder::sortEachRing(ScanGrid& grid)
{
  const std::size_t R = static_cast<std::size_t>(grid.num_rings);
  std::uint32_t* const next = bin_start_.data();
  const std::uint64_t* const unsorted = keys_tmp_.data();
  std::size_t m = 0;
  // Kept counts first: sortRing's bucket sort reuses bin_start_ (next). Each ring is sorted into a
  // one-ring buffer and split into indices and azimuths while its keys are still in L1.
  ring_kept_.resize(R);
  std::uint32_t largest = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    ring_kept_[r] = next[r] - grid.ring_begin[r];
    largest = std::max(largest, ring_kept_[r]);
    m += ring_kept_[r];
  }
  keys_.resize(largest);
  tmp_index_.resize(m);
  sorted_az_.resize(m);
  std::uint32_t kept = 0;
  for (std::size_t r = 0; r < R; ++r)
  {
    const std::uint32_t b = grid.ring_begin[r], k = ring_kept_[r];  // (before ring r's entry is rewritten)
    grid.ring_begin[r] = kept;
    sortRing(unsorted + b, keys_.data(), k);
    splitKeys(k, keys_.data(), tmp_index_.data() + kept, sorted_az_.data() + kept);
    kept += k;
  }
  grid.ring_begin[R] = kept;
}

void ScanGridBuilder::scatterInterleaved(std::size_t from, std::size_t to)
{
  // Points [from, to) into their rings' next slots, keys made a block at a time in a loop that
  // vectorizes. (Restrict locals: a key's store could alias next[], which would be reloaded.)
  const std::int32_t* __restrict const ring_of = ring_of_.data();
  const float* __restrict const paz = paz_.data();
  std::uint32_t* __restrict const next = bin_start_.data();
  std::uint64_t* __restrict const unsorted = keys_tmp_.data();
  constexpr std::size_t kBlock = 512;  // 4 KB of keys on the stack, in L1 until scattered
  constexpr std::size_t kScatterAhead = 32;  // keys (four lines)
  alignas(64) std::uint64_t keys[kBlock];
  for (std::size_t i0 = from; i0 < to; i0 += kBlock)
  {
    const std::size_t len = std::min(kBlock, to - i0);
    sortKeys(paz + i0, i0, len, keys);
    for (std::size_t j = 0; j < len; ++j)
    {
      const std::int32_t r = ring_of[i0 + j];
      if (r < 0) continue;
      // 16-64 interleaved store streams (one per ring) are more than hardware prefetch follows,
      // and their lines are cold: ask for the line kScatterAhead keys ahead of the ring's cursor.
      detail::prefetchForWrite(unsorted, (std::size_t{next[r]} + kScatterAhead) * sizeof *unsorted);
      unsorted[next[r]++] = keys[j];
    }
  }
}

void ScanGridBuilder::resolveFollowers(ScanGrid& grid)
{
  // In list order per ring, a follower's twin is a kept point (decided by removeDuplicates) or an
  // earlier follower (a third identical return), decided by then. The rings' runs advance side by
  // side, kBlock input points at a time, so nearby followers share the lines of state / grid_pos.
  PointState* const state = grid.state.data();
  std::int32_t* const grid_pos = grid.grid_pos.data();
  // Counted in a register: through `++(duplicate ? a : b)` each would wait on the store before.
  std::size_t duplicates = 0;
  const Follower* const followers = followers_.data();
  std::uint32_t* const runs = follower_runs_.data();  // each run's next follower, and its end
  const std::size_t num_runs = num_follower_runs_;
  constexpr std::size_t kBlock = 2048;  // input points
  for (std::size_t limit = kBlock; limit < grid.num_input + kBlock; limit += kBlock)
    for (std::size_t l = 0; l < num_runs; ++l)
    {
      std::uint32_t k = runs[2 * l];
      const std::uint32_t e = runs[2 * l + 1];
      for (; k < e && followers[k].point < limit; ++k)
      {
        const Follower& f = followers[k];
        const PointState twin = state[f.of];
        const PointState s = twin == PointState::OnGrid ? PointState::Duplicate : twin;
        state[f.point] = s;
        grid_pos[f.point] = grid_pos[f.of];  // the twin's position, or its representative's
        duplicates += s == PointState::Duplicate ? 1 : 0;
      }
      runs[2 * l] = k;
    }
  grid.num_duplicates += duplicates;
  grid.num_second_returns += num_followers_ - duplicates;
  grid.num_folded = num_followers_;
}

}  // namespace ring_curvature
