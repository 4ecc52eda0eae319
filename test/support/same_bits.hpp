// Bit-for-bit comparison of two arrays, for the tests that hold a SIMD form to its plain one.
#pragma once

#include <cstring>

namespace ring_curvature
{
namespace test
{
/// Same size and the same bits (NaN payloads and signed zeros included) in every element.
template <class A, class B>
bool sameBits(const A& a, const B& b)
{
  return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}
}  // namespace test
}  // namespace ring_curvature
