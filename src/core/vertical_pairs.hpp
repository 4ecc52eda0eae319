// The vertical unions' AVX-512 form (PrimitiveExtractor::extract): which runs of a ring unite
// with runs of the ring above it, eight positions at a time and without a branch on the data.
#pragma once

#include "ring_curvature/primitives.hpp"
#include "cpu_tuning.hpp"
#include "simd_clones.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{

/// The inputs of the vertical unions of one ring (n-1) with the ring above it (n).
struct VerticalRing
{
  std::uint32_t b, e;  // the ring above: [b, e)
  const PrimitiveExtractor::Run* __restrict runs;
  const Label* __restrict lab;
  const std::int32_t* __restrict up;
  const double* __restrict range;
  const float* __restrict azimuth;
  bool organized;
  double half_ratio, range_min;  // inRange's range_ratio * 0.5 * (ra + rb), left to right
  float az_tol;
  const std::uint32_t* __restrict run;
  std::uint32_t* parent;
};

/// No pair: the entry of a position that joins no run above.
constexpr std::uint64_t kNoVerticalPair = ~std::uint64_t{0};

#if defined(RC_SIMD_CLONES_ON)
/// The pairs of runs that positions [b0, e0) of ring n-1 join above, as the vertical unions
/// of primitives.cpp find them: position p of a wanted run rp = run[p] with a sample above
/// (up[p] >= 0) joins run rq = run[q] of the first of up[p], the one before and the one after
/// it (with the seam) that has p's label and is within Eq 19-20 (for up[p] itself on an
/// organized cloud Eq 19's azimuth is not asked). Each position's pair is rp | rq << 32, or
/// kNoVerticalPair; listed in `pairs` are those that differ from the pair of the position
/// before (the first position: from kNoVerticalPair) and are not kNoVerticalPair, in position
/// order. Returns how many: at most e0 - b0; `pairs` needs room for 8 more (it may write
/// whole vectors past the list). Reads V.run[], V.range[] and V.azimuth[] only
/// inside the rings, the labels up to e0 and e. Only with AVX-512F, DQ, BW and VL and POPCNT
/// (verticalPairsRuns says whether the CPU has them).
std::size_t verticalPairsAvx512(const VerticalRing& V, std::uint32_t b0, std::uint32_t e0, std::uint32_t none,
                                std::uint64_t* pairs);

/// Whether this CPU runs verticalPairsAvx512.
inline bool verticalPairsRuns()
{
  return detail::avx512Forms() && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("popcnt");
}
#endif

}  // namespace ring_curvature
