// Smoothness S of Eq 10 along one ring (FeatureComputer::computeRing's last feature).
#pragma once

#include <cstddef>

namespace ring_curvature
{

/// Entries of the `prefix` scratch that ringSmoothness needs for a ring of K samples.
inline std::size_t smoothnessScratch(int K, int w, bool closed)
{
  const std::size_t E = static_cast<std::size_t>(K) + 2 * static_cast<std::size_t>(closed ? w : 0);
  return 3 * (E + 1);
}

/// Smoothness of one ring's K samples (window +-w, w >= 1) into out[0, K) from its ranges `rho`, and
/// `rpf` in float padded by w each side; L and R the free links each side (capped above w), seg the
/// segments between gaps, `prefix` room for smoothnessScratch(K, w, closed) values.
void ringSmoothness(int K, int w, bool closed, bool detrend, const double* rho, const float* rpf, const int* L,
                    const int* R, const int* seg, int num_seg, double* prefix, float* out);

}  // namespace ring_curvature
