// Box, centroid and second moments of one primitive (PrimitiveExtractor::extract's sums).
#pragma once

#include "common/simd_clones.hpp"

#include <cstdint>

namespace ring_curvature
{

/// One primitive's box and centroid in float, lanes (x, y, z, z), and second moments about its mean
/// in double, (xx, yy, zx, zz) and (xy, yz), not yet divided by the number of points.
struct PrimitiveSums
{
  alignas(16) float lo[4], hi[4], centroid[4];
  alignas(32) double m[4];
  alignas(16) double mxy[2];
};

/// The sums over the np points of a primitive: its ng >= 1 grid points at grid positions sp[0, ng)
/// and np - ng duplicates of them. Where np > ng, grid point p stands for 1 + dup_count[p] points;
/// where np == ng, dup_count is not read (may be null). gx, gy, gz: the grid's coordinates.
void primitiveSums(const std::uint32_t* sp, std::uint32_t ng, std::uint32_t np, const std::uint32_t* dup_count,
                   const double* gx, const double* gy, const double* gz, PrimitiveSums& out);

}  // namespace ring_curvature
