// Reading one coordinate of an input record of any supported float type (shared by the grid's
// input pass and its gather).
#pragma once

#include <cstring>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{

inline double readCoord(const std::uint8_t* rec, const FieldView& f)
{
  if (f.type == ScalarType::Float32) return readFloat32(rec + f.offset);
  double d;
  std::memcpy(&d, rec + f.offset, sizeof d);
  return d;
}

}  // namespace ring_curvature
