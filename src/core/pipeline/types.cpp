#include "ring_curvature/types.hpp"

namespace ring_curvature
{

const char* labelName(Label l)
{
  switch (l)
  {
    case Label::None: return "none";
    case Label::Plane: return "plane";
    case Label::Edge: return "edge";
    case Label::Corner: return "corner";
    case Label::Rough: return "rough";
  }
  return "?";
}

std::size_t scalarSize(ScalarType t)
{
  switch (t)
  {
    case ScalarType::Int8:
    case ScalarType::UInt8: return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16: return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32: return 4;
    case ScalarType::Float64: return 8;
  }
  return 0;  // not a valid datatype: callers treat size 0 as an error
}

bool isIntegerType(ScalarType t)
{
  return t != ScalarType::Float32 && t != ScalarType::Float64 && scalarSize(t) != 0;
}

const char* scalarTypeName(ScalarType t)
{
  switch (t)
  {
    case ScalarType::Int8: return "int8";
    case ScalarType::UInt8: return "uint8";
    case ScalarType::Int16: return "int16";
    case ScalarType::UInt16: return "uint16";
    case ScalarType::Int32: return "int32";
    case ScalarType::UInt32: return "uint32";
    case ScalarType::Float32: return "float32";
    case ScalarType::Float64: return "float64";
  }
  return "unknown";
}

namespace
{
template <typename T>
T load(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof v);  // fields may be unaligned (packed layouts)
  return v;
}
}  // namespace

double readScalar(const std::uint8_t* p, ScalarType t)
{
  switch (t)
  {
    case ScalarType::Int8: return load<std::int8_t>(p);
    case ScalarType::UInt8: return load<std::uint8_t>(p);
    case ScalarType::Int16: return load<std::int16_t>(p);
    case ScalarType::UInt16: return load<std::uint16_t>(p);
    case ScalarType::Int32: return load<std::int32_t>(p);
    case ScalarType::UInt32: return load<std::uint32_t>(p);
    case ScalarType::Float32: return load<float>(p);
    case ScalarType::Float64: return load<double>(p);
  }
  return 0.0;
}

std::int64_t readInteger(const std::uint8_t* p, ScalarType t)
{
  // float types are rejected before reading; every integer type's values are exact in a double
  return isIntegerType(t) ? static_cast<std::int64_t>(readScalar(p, t)) : -1;
}

}  // namespace ring_curvature
