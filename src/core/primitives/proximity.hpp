// Eq 19-20 (Section 4.3): when two grid samples are close enough to join one primitive, for the
// primitives' unions (ring_unions.cpp).
#pragma once

#include "common/angles.hpp"

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

/// Eq 20: |ra - rb| <= max(range_ratio * 0.5 * (ra + rb), range_min).
inline bool inRange(double ra, double rb, double range_ratio, double range_min)
{
  return !(std::fabs(ra - rb) > std::max(range_ratio * 0.5 * (ra + rb), range_min));
}

/// Eq 19's azimuth difference of two samples.
inline float angDiff(float a, float b) { return circularDistance(a - b); }

}  // namespace ring_curvature
