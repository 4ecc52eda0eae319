// Scratch buffers that only grow: a resize down for a small frame or ring and up again for a
// larger one would zero-fill (and, past the capacity, allocate) the difference every time.
#pragma once

#include <cstddef>

namespace ring_curvature
{

/// Makes v hold at least n elements; never shrinks it.
template <class Vector>
inline void growTo(Vector& v, std::size_t n)
{
  if (v.size() < n) v.resize(n);
}

}  // namespace ring_curvature
