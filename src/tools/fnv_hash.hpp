// FNV-1a over bytes: fingerprints of outputs, so that a tool can tell whether two builds
// computed the same thing (an A/B timing of builds with different outputs compares different
// work).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ring_curvature
{
namespace bench
{

constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;

inline void hashBytes(std::uint64_t& h, const void* data, std::size_t n)
{
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i)
  {
    h ^= p[i];
    h *= 1099511628211ull;
  }
}

template <typename T>
void hashVector(std::uint64_t& h, const std::vector<T>& v)
{
  hashBytes(h, v.data(), v.size() * sizeof(T));
}

}  // namespace bench
}  // namespace ring_curvature
