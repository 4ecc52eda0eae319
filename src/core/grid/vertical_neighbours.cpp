// The nearest sample on the ring above each grid position (ScanGrid::up): a merge walk along two
// sorted rings and the choice among three candidates for unorganized clouds, the same column one
// row up for organized ones.
#include "ring_curvature/scan_grid.hpp"
#include "grid/scan_grid_builder.hpp"

#include "common/angles.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

namespace
{

// The nearest sample above each p of ring (b, e), up[p] being the last of ring (ub, ue) at or before
// p's azimuth (or ub): of up[p], its successor (around the seam) and the ring's last, the circularly
// nearest (first of equals; circularDistance is |wrapPi| exactly). Branch-free: a coin toss each.
RC_SIMD_CLONES void nearestAbove(std::uint32_t b, std::uint32_t e, std::uint32_t ub, std::uint32_t ue,
                                 const float* __restrict az, std::int32_t* __restrict up)
{
  const float last = az[ue - 1];
  for (std::uint32_t p = b; p < e; ++p)
  {
    const float a = az[p];
    const std::uint32_t q = static_cast<std::uint32_t>(up[p]);
    const std::uint32_t c1 = q + 1 < ue ? q + 1 : ub;
    const float d0 = circularDistance(az[q] - a), d1 = circularDistance(az[c1] - a),
                d2 = circularDistance(last - a);
    std::uint32_t best = d1 < d0 ? c1 : q;
    const float bd = d1 < d0 ? d1 : d0;
    best = d2 < bd ? ue - 1 : best;
    up[p] = static_cast<std::int32_t>(best);
  }
}

// The walk for a ring (b, e) under the ring above (ub, ue): up[p] the last sample above at or
// before p's azimuth (or ub), which nearestAbove then turns into the nearest. The same walk gives
// the ring above its `below`: a sample above passed at p lies after p - 1 and at or before p, so
// p - 1 it is but for equal azimuths (rare: a test, not a walk); the first is walked from b, and
// those never passed lie after the whole ring.
void walkAbove(const float* az, std::int32_t* up, std::int32_t* below, std::uint32_t b, std::uint32_t e,
               std::uint32_t ub, std::uint32_t ue)
{
  const auto lastAtOrBefore = [&](std::uint32_t from, float a) {
    while (from + 1 < e && az[from + 1] <= a) ++from;
    return static_cast<std::int32_t>(from);
  };
  std::uint32_t q = ub;
  for (std::uint32_t p = b; p < e; ++p)
  {
    const float a = az[p];
    while (q + 1 < ue && az[q + 1] <= a)
    {
      ++q;
      below[q] = p > b && az[q] < a ? static_cast<std::int32_t>(p - 1) : lastAtOrBefore(p > b ? p - 1 : b, az[q]);
    }
    up[p] = static_cast<std::int32_t>(q);
  }
  below[ub] = lastAtOrBefore(b, az[ub]);
  std::fill(below + q + 1, below + ue, static_cast<std::int32_t>(e - 1));
}

// Organized: the grid position of the point one row up of each position p < m.
RC_SIMD_CLONES void upOrganized(std::size_t m, std::size_t width, const std::uint32_t* __restrict index,
                                const std::int32_t* __restrict grid_pos, std::int32_t* __restrict up)
{
  for (std::size_t p = 0; p < m; ++p) up[p] = grid_pos[index[p] + width];
}

}  // namespace

void ScanGridBuilder::findVerticalNeighbours(ScanGrid& grid)
{
  const std::size_t m = grid.size();
  if (grid.organized)
  {
    // The same column one row up: its grid_pos is -1 for a point off the grid (no duplicates when
    // organized; the input pass set all to -1), so no test per point. The top ring has none above.
    grid.up.resize(m);
    const std::size_t width = grid.num_input / static_cast<std::size_t>(grid.num_rings);
    const std::uint32_t top = grid.ring_begin[static_cast<std::size_t>(grid.num_rings) - 1];
    upOrganized(top, width, grid.index.data(), grid.grid_pos.data(), grid.up.data());
    std::fill(grid.up.begin() + top, grid.up.end(), -1);
    return;
  }
  // Positions of a ring followed by a non-empty one are written below; only the others get -1.
  grid.up.resize(m);
  grid.below.resize(m);
  // Walk the two sorted rings together to the last sample above at or before each azimuth; the
  // choice of the nearest is a loop of its own (nearestAbove) so that it vectorizes.
  const float* const az = grid.azimuth.data();
  std::int32_t* const up = grid.up.data();
  std::int32_t* const below = grid.below.data();
  if (grid.num_rings > 0) std::fill(below, below + grid.ring_begin[1], -1);  // nothing below ring 0
  for (int n = 0; n + 1 < grid.num_rings; ++n)
  {
    const std::uint32_t b = grid.ring_begin[static_cast<std::size_t>(n)], e = grid.ring_begin[static_cast<std::size_t>(n) + 1];
    const std::uint32_t ub = e, ue = grid.ring_begin[static_cast<std::size_t>(n) + 2];
    if (ub == ue || b == e)
    {
      std::fill(up + b, up + e, -1);
      std::fill(below + ub, below + ue, -1);
      continue;
    }
    walkAbove(az, up, below, b, e, ub, ue);
    nearestAbove(b, e, ub, ue, az, up);
  }
  if (grid.num_rings > 0)  // the top ring has none above it
    std::fill(up + grid.ring_begin[static_cast<std::size_t>(grid.num_rings) - 1], up + m, -1);
}

}  // namespace ring_curvature
