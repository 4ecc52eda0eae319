// Per-point features along each ring: discrete geodesic curvature (Eq 6-9), smoothness S
// (Eq 10) and discontinuity D (Eq 11), with the variants READING_NOTES.md motivates.
#pragma once

#include <vector>

#include "ring_curvature/params.hpp"
#include "ring_curvature/scan_grid.hpp"

namespace ring_curvature
{

/// Features per grid position; NaN where a feature is undefined (too few neighbours on the
/// ring's curve, e.g. at a gap), never computed across a gap.
struct Features
{
  std::vector<float> curvature;      ///< kappa_g [1/m]
  std::vector<float> turning;        ///< turning angle [rad] behind kappa (for thresholds)
  std::vector<float> smoothness;     ///< S [m^2]
  std::vector<float> discontinuity;  ///< D (Paper: [0,1]; Jump: relative prediction error)
};

/// Which version of the core's hot loops this CPU runs: "avx2", "avx2, avx512f (...)" (the
/// feature kernels and the hand-written kernels listed in AVX-512) or "baseline" (x86-64 without
/// AVX2, other architectures, or a build with RC_SIMD_CLONES=OFF). All give the same bits.
const char* coreLoopsIsa();

class FeatureComputer
{
public:
  void compute(const ScanGrid& grid, const Params& params, Features& out);

private:
  void computeRing(const ScanGrid& grid, const Params& params, int ring, Features& out);
  // scratch for one ring (sized to the largest ring, reused)
  std::vector<float> rho_pad_f_;      // the ring's ranges in float, padded with the seam's neighbours
  std::vector<float> az_pad_;         // and its azimuths
  std::vector<int> runs_;             // links free to the left (first K) and right (next K) of each sample
  std::vector<int> seg_;              // the ring's segments between gaps (their first samples)
  std::vector<float> jump_;           // discontinuity of each link (k - 1, k), and the seam's again
  std::vector<double> prefix_;        // prefix sums for windowed statistics
  std::vector<int> half_;             // chord mode: samples per half chord
  std::vector<float> chord_;          // chord mode: chord products per sample, and the chords' ends
  std::vector<double> turn_len_;      // other modes: turning angle and arc length per sample
};

}  // namespace ring_curvature
