// The lane table of left-packing: for each 8-bit mask the lanes of its set bits in order, which
// move the marked lanes of an eight-lane vector to its front (the thresholds' candidate copies, the
// organized pass's placement).
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
