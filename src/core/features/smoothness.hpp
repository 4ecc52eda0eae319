// Smoothness S of Eq 10 along one ring (FeatureComputer::computeRing's last feature).
#pragma once

#include <cstddef>

namespace ring_curvature
{

/// Entries of the `prefix` scratch that ringSmoothness needs for a ring of K samples.
inline std::size_t smoothnessScratch(int K, int w, bool closed)
{
  const std::size_t E = static_cast<std::size_t>(K) + 2 * static_cast<std::size_t>(closed ? w : 0);
  return 3 * (E + 1) + (closed ? E : 0);  // the sums, and a closed ring's ranges across its seam
}

/// Smoothness of the K samples of one ring (window of +-w samples, w >= 1) into out[0, K): `rho`
/// holds the ring's K ranges (windows of a closed ring wrap across its seam), `rpf` the same in
/// float padded with w samples on each side (the neighbours across the seam of a closed ring;
/// Detrended with w <= 4 forms its full windows from them), L and R the links free to the left and right of each sample (capped above w),
/// seg[0, num_seg) the segments between gaps (see computeRing), and `prefix` room for
/// smoothnessScratch(K, w, closed) values.
void ringSmoothness(int K, int w, bool closed, bool detrend, const double* rho, const float* rpf, const int* L,
                    const int* R, const int* seg, int num_seg, double* prefix, float* out);

}  // namespace ring_curvature
