// A ring of the grid and the position on it of an index a few samples before or after another
// (across the seam of a closed ring), shared by the features, the smoothness's windows and the
// inter-ring steps.
#pragma once

#include "ring_curvature/scan_grid.hpp"

#include <cstdint>

namespace ring_curvature
{

/// i wrapped into [0, K) (K > 0). Offsets are a few samples, so one add or subtract wraps them
/// instead of a 64-bit `%` per access; `%` remains for rings shorter than the offset.
inline std::int64_t wrapRingIndex(std::int64_t i, std::int64_t K)
{
  if (i < 0) i += K;
  else if (i >= K) i -= K;
  if (i < 0 || i >= K)
  {
    i %= K;
    if (i < 0) i += K;
  }
  return i;
}

/// One ring of the grid: positions [b, b + K), and circular neighbour access.
struct RingSpan
{
  std::uint32_t b, K;
  bool closed;
  RingSpan(const ScanGrid& g, int n)
      : b(g.ring_begin[static_cast<std::size_t>(n)]),
        K(g.ring_begin[static_cast<std::size_t>(n) + 1] - b),
        closed(g.ring_closed[static_cast<std::size_t>(n)] != 0)
  {
  }
  std::uint32_t end() const { return b + K; }
  std::uint32_t pos(std::int64_t k) const
  {
    return b + static_cast<std::uint32_t>(wrapRingIndex(k, static_cast<std::int64_t>(K)));
  }
};

/// The linked ring neighbours of a ring's local index k: -1 across a gap or past an open end.
struct RingLinks
{
  const ScanGrid& g;
  const RingSpan& s;
  std::int64_t prev(std::uint32_t k) const
  {
    if (k == 0 && !s.closed) return -1;
    return g.linked[s.b + k] ? static_cast<std::int64_t>(s.pos(static_cast<std::int64_t>(k) - 1)) : -1;
  }
  std::int64_t next(std::uint32_t k) const
  {
    if (k + 1 == s.K && !s.closed) return -1;
    const std::uint32_t q = s.pos(static_cast<std::int64_t>(k) + 1);
    return g.linked[q] ? static_cast<std::int64_t>(q) : -1;
  }
};

}  // namespace ring_curvature
