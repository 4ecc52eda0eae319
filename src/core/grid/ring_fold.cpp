// Folding of identical dual returns, ring by ring: after the scatter by ring, a pass over each
// ring's keys in firing order keeps the points that differ from both keys before them and lists
// the others as followers of their twin (resolveFollowers gives them its verdict).
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

#include <cstddef>
#include <cstring>

namespace ring_curvature
{

namespace
{
inline std::uint64_t rangeBits(const double* range, std::uint64_t key)
{
  std::uint64_t b;
  std::memcpy(&b, &range[static_cast<std::uint32_t>(key)], sizeof b);
  return b;
}
}  // namespace

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

}  // namespace ring_curvature
