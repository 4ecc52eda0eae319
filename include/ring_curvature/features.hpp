// Per-point features along each ring: discrete geodesic curvature (Eq 6-9), smoothness S
// (Eq 10) and discontinuity D (Eq 11), with the variants READING_NOTES.md motivates.
#pragma once

#include <vector>

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

/// Which clone of the core's hot loops this CPU runs: "avx2 clones", "baseline" (x86-64 without
/// AVX2) or "portable" (other architectures, or a build with RC_SIMD_CLONES=OFF). All give the
/// same bits.
const char* coreLoopsIsa();

}  // namespace ring_curvature
