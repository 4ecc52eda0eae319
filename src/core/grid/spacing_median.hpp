// The median azimuth spacing of a frame, by selection over the bits of the spacings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ring_curvature
{

/// The grid's measured azimuth resolution from the spacings d[0, total) of neighbouring samples on
/// a ring (each >= 0, or NaN): the element of rank n / 2 of the n kept ones (above 1e-5 rad: not a
/// duplicate; below 5 deg: not a gap), as nth_element gives; `none` when none is kept. A class of
/// its own, keeping its scratch between frames, so that the tests reach both of its paths.
class SpacingMedian
{
public:
  /// d is overwritten when the frame is small or the sample's bracket misses.
  float operator()(float* d, std::size_t total, float none);
  /// Whether the last call found the median inside its sample's bracket (else it selected among all).
  bool bracketed() const { return bracketed_; }

private:
  bool fromBracket(const float* d, std::size_t total, float& median);
  std::vector<float> inside_;  // the kept spacings near the median
  bool bracketed_ = false;
};

}  // namespace ring_curvature
