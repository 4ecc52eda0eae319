// The position on a ring of K samples of an index a few samples before or after it (across the
// seam of a closed ring), shared by the features' neighbour look-ups and the smoothness's windows.
#pragma once

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

}  // namespace ring_curvature
