// Orders the valid points of each ring by azimuth in O(n): a counting sort by ring, then per
// ring the sort of ring_order.cpp. Identical dual returns are folded on the way and given their
// twin's verdict afterwards.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"
#include "common/float_bits.hpp"
#include "grid/sort_keys.hpp"

#include "common/angles.hpp"
#include "common/grow.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace ring_curvature
{

using detail::keyAzimuth;
using detail::keyIndex;
using detail::sortKey;

namespace
{

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

// The bits of the range of the point a key names (compared as bits by foldRing).
inline std::uint64_t rangeBits(const double* range, std::uint64_t key)
{
  std::uint64_t b;
  std::memcpy(&b, &range[static_cast<std::uint32_t>(key)], sizeof b);
  return b;
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
  unfolded_largest_ = 0;
  for (std::size_t r = 0; r < R; ++r) unfolded_largest_ = std::max(unfolded_largest_, ring_count_[r + 1]);
  scatterKeys(n);
  //    Each ring's keys, now contiguous in firing order, fold identical dual returns (azimuth and
  //    range of one of the two keys before): kept off the sort, they get their twin's state and
  //    grid position, removeDuplicates' verdict exactly (same firing, never a representative, same
  //    range). Needs same_firing > 0. If the first kFoldProbe keys fold nothing, the rest stay as is.
  prange_[n] = -1.0;  // no point's range: foldRing's start value (readPoints leaves room for it)
  growTo(followers_, n + 1);  // (foldRing writes one entry past the count)
  std::uint32_t* const next = bin_start_.data();
  std::size_t num_followers = 0, tested = 0;
  for (std::size_t r = 0; fold_identical && r < R && (num_followers > 0 || tested < kFoldProbe); ++r)
  {
    const std::uint32_t b = grid.ring_begin[r], k = next[r] - b;
    next[r] = b + foldRing(keys_tmp_.data() + b, k, n, prange_.data(), followers_.data(), num_followers);
    tested += k;
  }
  num_followers_ = num_followers;
  sortEachRing(grid);
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

void ScanGridBuilder::scatterKeys(std::size_t n)
{
  // Points into their rings' next slots, keys made a block at a time in a loop that vectorizes.
  // (Restrict locals: a key's store could alias next[], which would be reloaded.)
  const std::int32_t* __restrict const ring_of = ring_of_.data();
  const float* __restrict const paz = paz_.data();
  std::uint32_t* __restrict const next = bin_start_.data();
  std::uint64_t* __restrict const unsorted = keys_tmp_.data();
  constexpr std::size_t kBlock = 512;  // 4 KB of keys on the stack, in L1 until scattered
  alignas(64) std::uint64_t keys[kBlock];
  for (std::size_t i0 = 0; i0 < n; i0 += kBlock)
  {
    const std::size_t len = std::min(kBlock, n - i0);
    sortKeys(paz + i0, i0, len, keys);
    for (std::size_t j = 0; j < len; ++j)
    {
      const std::int32_t r = ring_of[i0 + j];
      if (r < 0) continue;
      unsorted[next[r]++] = keys[j];
    }
  }
}

// A pass over one ring's keys in firing order keeps the points that differ from both keys before
// them and lists the others as followers of their twin (resolveFollowers gives them its verdict).
std::uint32_t ScanGridBuilder::foldRing(std::uint64_t* keys, std::uint32_t k, std::uint64_t sentinel,
                                        const double* range, Follower* followers, std::size_t& num_followers)
{
  static_assert(sizeof(Follower) == sizeof(std::uint64_t) && offsetof(Follower, point) == 0 &&
                    offsetof(Follower, of) == sizeof(std::uint32_t),
                "a Follower is written as one 64-bit word: point low, twin high");
  // Key j follows when its azimuth key and range bits equal those of raw key j - 1 or j - 2 (p1, p2;
  // sentinels at first). Kept keys pack from the front (w <= j). Branch-free: folding is a coin toss.
  std::uint64_t p1 = sentinel, p2 = sentinel;
  std::uint64_t r1 = rangeBits(range, p1), r2 = rangeBits(range, p2);
  std::uint32_t w = 0;
  for (std::uint32_t j = 0; j < k; ++j)
  {
    const std::uint64_t key = keys[j], r = rangeBits(range, key);
    const bool same1 = (((key ^ p1) >> 32) | (r ^ r1)) == 0;
    const bool same2 = (((key ^ p2) >> 32) | (r ^ r2)) == 0;
    const bool same = same1 | same2;
    // point in the low half, its twin in the high half: the layout of a Follower
    const std::uint64_t entry = (key & 0xFFFFFFFFu) | ((same1 ? p1 : p2) << 32);
    std::memcpy(&followers[num_followers], &entry, sizeof entry);
    num_followers += same ? 1 : 0;
    keys[w] = key;
    w += same ? 0 : 1;
    p2 = p1;
    r2 = r1;
    p1 = key;
    r1 = r;
  }
  return w;
}

void ScanGridBuilder::resolveFollowers(ScanGrid& grid)
{
  // In list order, a follower's twin is a kept point (decided by removeDuplicates) or an earlier
  // follower of its ring (a third identical return), decided by then.
  PointState* const state = grid.state.data();
  std::int32_t* const grid_pos = grid.grid_pos.data();
  // Counted in a register: through `++(duplicate ? a : b)` each would wait on the store before.
  std::size_t duplicates = 0;
  for (std::size_t k = 0; k < num_followers_; ++k)
  {
    const Follower& f = followers_[k];
    const PointState twin = state[f.of];
    const PointState s = twin == PointState::OnGrid ? PointState::Duplicate : twin;
    state[f.point] = s;
    grid_pos[f.point] = grid_pos[f.of];  // the twin's position, or its representative's
    duplicates += s == PointState::Duplicate ? 1 : 0;
  }
  grid.num_duplicates += duplicates;
  grid.num_second_returns += num_followers_ - duplicates;
  grid.num_folded = num_followers_;
}

}  // namespace ring_curvature
