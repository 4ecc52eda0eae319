// For each 8-bit mask, the lanes of its set bits in order: the lane order that moves the marked
// lanes of an eight-lane vector to its front (left-packing), or the offsets of the marked
// elements of a group of eight. Shared by the thresholds' candidate compaction, the grid's
// Duplicate list and the measured resolution's bracket pass.
#pragma once

#include <cstdint>

namespace ring_curvature
{

struct CompressTable
{
  std::int32_t lane[256][8];
};
constexpr CompressTable makeCompressTable()
{
  CompressTable t{};
  for (int mask = 0; mask < 256; ++mask)
    for (int l = 0, j = 0; l < 8; ++l)
      if ((mask >> l) & 1) t.lane[mask][j++] = l;
  return t;
}
inline constexpr CompressTable kCompress = makeCompressTable();

}  // namespace ring_curvature
