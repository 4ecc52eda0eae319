// Basic types shared by the core library: labels, a non-owning view of interleaved point
// records (the layout of a sensor_msgs/PointCloud2, without depending on ROS), and a status.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace ring_curvature
{

/// Per-point geometric label. Values are part of the output format (field `label`).
enum class Label : std::uint8_t
{
  None = 0,    ///< invalid return, not on the scan grid, or not classified
  Plane = 1,   ///< locally flat along the ring (also gently curved smooth surfaces)
  Edge = 2,    ///< crease: the ring turns sharply while range stays continuous
  Corner = 3,  ///< sharp turn that coincides with a range discontinuity (depth jump)
  Rough = 4,   ///< high residual range variance (vegetation, clutter)
};
constexpr int kNumLabels = 5;
const char* labelName(Label l);

/// Scalar types of interleaved fields (mirrors sensor_msgs::PointField datatypes).
enum class ScalarType : std::uint8_t
{
  Int8 = 1, UInt8 = 2, Int16 = 3, UInt16 = 4, Int32 = 5, UInt32 = 6, Float32 = 7, Float64 = 8
};
std::size_t scalarSize(ScalarType t);
bool isIntegerType(ScalarType t);
const char* scalarTypeName(ScalarType t);

/// Where one field lives inside a point record.
struct FieldView
{
  std::int64_t offset = -1;  ///< byte offset inside the point record, -1 when absent
  ScalarType type = ScalarType::Float32;
  bool present() const { return offset >= 0; }
};

/// Non-owning view of a cloud of interleaved point records, read in place (zero copy).
/// Records are little-endian; fields may be unaligned (e.g. velodyne's packed 22-byte XYZIRT).
struct PointCloudView
{
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;    ///< bytes available at `data`
  std::uint32_t width = 0;      ///< points per row
  std::uint32_t height = 0;     ///< rows; > 1 means organized (row = beam, column = azimuth)
  std::uint32_t point_step = 0; ///< bytes per point record
  std::uint32_t row_step = 0;   ///< bytes per row
  FieldView x, y, z;            ///< required, Float32 or Float64
  FieldView ring;               ///< integer type; optional when organized or ring_from_elevation
  FieldView time;               ///< optional; the grid ignores it, the LOAM sets read it
  double time_scale = 1.0;      ///< seconds per unit of `time` (1e-9 for nanoseconds)
  FieldView intensity;          ///< optional

  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
  bool organized() const { return height > 1; }
  const std::uint8_t* record(std::size_t i) const
  {
    if (height == 1) return data + i * point_step;  // unorganized: no division per look-up
    return data + (i / width) * static_cast<std::size_t>(row_step) + (i % width) * point_step;
  }
};

/// Reads one scalar of any type at an unaligned address as double / int64.
double readScalar(const std::uint8_t* p, ScalarType t);
std::int64_t readInteger(const std::uint8_t* p, ScalarType t);
inline float readFloat32(const std::uint8_t* p)
{
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Result of an operation that can reject its input. The message names the problem.
struct Status
{
  bool ok = true;
  std::string message;
  static Status success() { return {}; }
  static Status error(std::string msg) { return {false, std::move(msg)}; }
  explicit operator bool() const { return ok; }
};

}  // namespace ring_curvature
