// cutRing's AVX2 and AVX-512 forms and the index fill's AVX2 form (PrimitiveExtractor::extract),
// in a file of its own: primitives.cpp would otherwise outgrow the 600-line limit.
#pragma once

#include "ring_curvature/primitives.hpp"
#include "simd_clones.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{

#if defined(RC_SIMD_CLONES_ON)
/// Cuts ring [b, e) into runs as cutRing in primitives.cpp does (the same run ids, runs[],
/// parent[], comp[] and return value), eight positions at a time. Wanted labels: 1 to
/// num_wanted. Reads join[] up to e + 8 and writes run[] up to e + 7 (the caller leaves room);
/// begins and ends: scratch of at least e - b + 8 entries each. Only with AVX2 and POPCNT.
std::size_t cutRingAvx2(std::uint32_t b, std::uint32_t e, const Label* lab, const std::uint8_t* join,
                        std::uint8_t num_wanted, std::uint32_t none, std::uint32_t* parent, std::uint32_t* run,
                        std::int32_t* comp, PrimitiveExtractor::Run* runs, std::size_t num_runs,
                        std::uint32_t* begins, std::uint32_t* ends);

/// extract's index fill (indices, slot_pos, of_grid, the primitives' rings) with AVX2.
void fillRunsAvx2(const PrimitiveExtractor::Run* runs, std::size_t num_runs, const std::uint32_t* parent,
                  const std::int32_t* comp, const std::uint32_t* ring_begin, PrimitiveInfo* prims,
                  const std::uint32_t* index, std::uint32_t* indices, std::uint32_t* slot_pos, std::int32_t* of_grid,
                  std::uint32_t m);

/// cutRingAvx2 sixteen positions at a time: the same contract, but reads join[] up to e + 16,
/// writes run[] up to e + 15, and begins / ends need e - b + 16 entries. Only with AVX-512F and
/// POPCNT.
std::size_t cutRingAvx512(std::uint32_t b, std::uint32_t e, const Label* lab, const std::uint8_t* join,
                          std::uint8_t num_wanted, std::uint32_t none, std::uint32_t* parent, std::uint32_t* run,
                          std::int32_t* comp, PrimitiveExtractor::Run* runs, std::size_t num_runs,
                          std::uint32_t* begins, std::uint32_t* ends);

#endif

}  // namespace ring_curvature
