// Lane tables: for each 8-bit mask the lanes of its set bits in order (moving the marked lanes of an
// eight-lane vector to its front: left-packing, as the thresholds' candidate compaction does), the
// same for four 64-bit elements, and each 8-bit mask's prefix counts.
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

/// For each 4-bit mask, the 32-bit lanes that move the marked 64-bit elements of a four-element
/// vector to its front (two lanes an element): left-packing doubles or 64-bit keys.
struct PairTable
{
  std::int32_t lane[16][8];
};
constexpr PairTable makePairTable()
{
  PairTable t{};
  for (int mask = 0; mask < 16; ++mask)
    for (int l = 0, j = 0; l < 4; ++l)
      if ((mask >> l) & 1)
      {
        t.lane[mask][2 * j] = 2 * l;
        t.lane[mask][2 * j + 1] = 2 * l + 1;
        ++j;
      }
  return t;
}
inline constexpr PairTable kPairs = makePairTable();

}  // namespace ring_curvature
