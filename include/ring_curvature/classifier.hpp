// The thresholds of one ring (Algorithm 1's quartiles or the robust variant), as the pipeline
// reports them for tools and tests.
#pragma once

#include "ring_curvature/features.hpp"

namespace ring_curvature
{

/// Thresholds of one ring (low / high for each feature).
struct RingThresholds
{
  float curvature_low = 0, curvature_high = 0;
  float smoothness_high = 0;
  float discontinuity_low = 0, discontinuity_high = 0;
};

}  // namespace ring_curvature
