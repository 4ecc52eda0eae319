// The ring sort's keys: (azimuth, input index) in one 64-bit integer.
#pragma once

#include "common/float_bits.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

// The sort key: the azimuth's bits mapped to an unsigned key of the same order (-0 made +0 first,
// so equal floats give equal keys) above the input index: one 64-bit comparison is the order.
inline std::uint32_t azimuthKey(float azimuth) { return detail::orderedKey(azimuth + 0.0f); }
inline float keyAzimuth(std::uint64_t key)
{
  const auto k = static_cast<std::uint32_t>(key >> 32);
  return detail::bitsFloat((k & 0x80000000u) != 0 ? k ^ 0x80000000u : ~k);
}
inline std::uint32_t keyIndex(std::uint64_t key) { return static_cast<std::uint32_t>(key); }
inline std::uint64_t sortKey(float azimuth, std::size_t i)
{
  return (static_cast<std::uint64_t>(azimuthKey(azimuth)) << 32) | static_cast<std::uint32_t>(i);
}

}  // namespace detail
}  // namespace ring_curvature
