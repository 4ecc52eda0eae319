// Synthetic LiDAR frames packed into arbitrary point layouts, for the robustness tests and the
// fuzz target. A frame is a scan of a closed box room from its inside, so every ring sees walls
// (Plane), vertical creases (Edge) and, with a pillar, depth jumps: a good frame that exercises
// every stage of the pipeline. ROS-free on purpose: the core tests and the sanitizer build use it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{
namespace test
{

struct SyntheticPoint
{
  float x = 0, y = 0, z = 0, intensity = 0;
  std::int64_t ring = 0;
  double time = 0;
};

/// Where each field goes in a point record; absent fields have offset -1.
struct Layout
{
  std::uint32_t point_step = 0;
  FieldView x, y, z, ring, time, intensity;
};

/// velodyne_pointcloud's packed 22-byte XYZIRT (unaligned floats after the uint16 ring).
inline Layout velodyneLayout()
{
  Layout l;
  l.point_step = 22;
  l.x = {0, ScalarType::Float32};
  l.y = {4, ScalarType::Float32};
  l.z = {8, ScalarType::Float32};
  l.intensity = {12, ScalarType::Float32};
  l.ring = {16, ScalarType::UInt16};
  l.time = {18, ScalarType::Float32};
  return l;
}

/// ouster-ros "original" 48-byte layout (ring uint16 at 26, t uint32 ns at 20).
inline Layout ousterLayout()
{
  Layout l;
  l.point_step = 48;
  l.x = {0, ScalarType::Float32};
  l.y = {4, ScalarType::Float32};
  l.z = {8, ScalarType::Float32};
  l.intensity = {16, ScalarType::Float32};
  l.time = {20, ScalarType::UInt32};
  l.ring = {26, ScalarType::UInt16};
  return l;
}

/// An owning cloud: bytes plus the PointCloud2-like header. view() points into `data`, so take
/// a fresh view after every change to the buffer.
struct Cloud
{
  std::vector<std::uint8_t> data;
  std::uint32_t width = 0, height = 0, point_step = 0, row_step = 0;
  Layout layout;

  PointCloudView view() const
  {
    PointCloudView v;
    v.data = data.empty() ? nullptr : data.data();
    v.data_size = data.size();
    v.width = width;
    v.height = height;
    v.point_step = point_step;
    v.row_step = row_step;
    v.x = layout.x;
    v.y = layout.y;
    v.z = layout.z;
    v.ring = layout.ring;
    v.time = layout.time;
    v.intensity = layout.intensity;
    return v;
  }
  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
};

inline void writeScalar(std::uint8_t* p, ScalarType t, double v)
{
  // memcpy, because records may be packed and unaligned like velodyne's
  auto put = [p](auto value) { std::memcpy(p, &value, sizeof value); };
  switch (t)
  {
    case ScalarType::Int8: put(static_cast<std::int8_t>(v)); break;
    case ScalarType::UInt8: put(static_cast<std::uint8_t>(v)); break;
    case ScalarType::Int16: put(static_cast<std::int16_t>(v)); break;
    case ScalarType::UInt16: put(static_cast<std::uint16_t>(v)); break;
    case ScalarType::Int32: put(static_cast<std::int32_t>(v)); break;
    case ScalarType::UInt32: put(static_cast<std::uint32_t>(v)); break;
    case ScalarType::Float32: put(static_cast<float>(v)); break;
    case ScalarType::Float64: put(v); break;
  }
}

inline void writeField(std::uint8_t* rec, const FieldView& f, double v)
{
  if (f.present())
    writeScalar(rec + f.offset, f.type, v);
}

/// Packs points (row-major, width x height) into `layout`, with `row_padding` spare bytes at
/// the end of every row (legal in PointCloud2: row_step may exceed width * point_step).
inline Cloud pack(const std::vector<SyntheticPoint>& pts, const Layout& layout, std::uint32_t width,
                  std::uint32_t height, std::uint32_t row_padding = 0)
{
  Cloud c;
  c.layout = layout;
  c.width = width;
  c.height = height;
  c.point_step = layout.point_step;
  c.row_step = width * layout.point_step + row_padding;
  c.data.assign(static_cast<std::size_t>(c.row_step) * height, 0xA5);  // padding is garbage
  for (std::size_t i = 0; i < pts.size() && i < c.size(); ++i)
  {
    std::uint8_t* rec = c.data.data() + (i / width) * c.row_step + (i % width) * c.point_step;
    const SyntheticPoint& p = pts[i];
    writeField(rec, layout.x, p.x);
    writeField(rec, layout.y, p.y);
    writeField(rec, layout.z, p.z);
    writeField(rec, layout.intensity, p.intensity);
    writeField(rec, layout.ring, static_cast<double>(p.ring));
    writeField(rec, layout.time, p.time);
  }
  return c;
}

/// Range from the origin along unit direction d to the inside of the room: an axis-aligned box
/// (x in [-6, 7], y in [-4, 5], z in [-1.5, 2.5]) with a square pillar (x, y in [2, 2.6]).
inline float roomRange(double dx, double dy, double dz)
{
  double t = std::numeric_limits<double>::infinity();
  auto wall = [&t](double d, double lo, double hi) {
    if (d > 1e-12) t = std::min(t, hi / d);
    if (d < -1e-12) t = std::min(t, lo / d);
  };
  wall(dx, -6.0, 7.0);
  wall(dy, -4.0, 5.0);
  wall(dz, -1.5, 2.5);
  // pillar: slab intersection, entered from outside
  double tmin = 0, tmax = t;
  for (int a = 0; a < 2; ++a)
  {
    const double d = a == 0 ? dx : dy;
    if (std::fabs(d) < 1e-12)
    {
      tmin = 1, tmax = 0;  // parallel to a slab that does not contain the origin: miss
      break;
    }
    double t0 = 2.0 / d, t1 = 2.6 / d;
    if (t0 > t1) std::swap(t0, t1);
    tmin = std::max(tmin, t0);
    tmax = std::min(tmax, t1);
  }
  if (tmin < tmax && tmin > 0) t = tmin;
  return static_cast<float>(t);
}

/// One rotation of a `rings`-beam sensor with `samples` firings per rotation, in firing order
/// (for each azimuth, every ring), like velodyne's unorganized clouds. Beams span -15..+15 deg;
/// each ring has a small azimuth offset, as real sensors do.
inline std::vector<SyntheticPoint> roomScan(int rings, int samples)
{
  std::vector<SyntheticPoint> pts;
  pts.reserve(static_cast<std::size_t>(rings) * samples);
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < samples; ++k)
    for (int n = 0; n < rings; ++n)
    {
      const double elev = rings == 1 ? 0.0 : (-15.0 + 30.0 * n / (rings - 1)) * pi / 180.0;
      const double az = -pi + 2 * pi * (k + 0.1 * (n % 4) / 4.0) / samples;
      const double dx = std::cos(elev) * std::cos(az), dy = std::cos(elev) * std::sin(az),
                   dz = std::sin(elev);
      const float r = roomRange(dx, dy, dz);
      SyntheticPoint p;
      p.x = static_cast<float>(r * dx);
      p.y = static_cast<float>(r * dy);
      p.z = static_cast<float>(r * dz);
      p.intensity = static_cast<float>(n);
      p.ring = n;
      p.time = 0.1 * k / samples;
      pts.push_back(p);
    }
  return pts;
}

/// The same scan as an organized cloud: row = ring, column = azimuth index.
inline std::vector<SyntheticPoint> toOrganized(const std::vector<SyntheticPoint>& firing_order,
                                               int rings, int samples)
{
  std::vector<SyntheticPoint> out(firing_order.size());
  for (int k = 0; k < samples; ++k)
    for (int n = 0; n < rings; ++n)
      out[static_cast<std::size_t>(n) * samples + k] =
          firing_order[static_cast<std::size_t>(k) * rings + n];
  return out;
}

/// A good unorganized VLP-16-like frame in velodyne's packed layout.
inline Cloud goodCloud(int rings = 16, int samples = 900)
{
  return pack(roomScan(rings, samples), velodyneLayout(),
              static_cast<std::uint32_t>(rings * samples), 1);
}

}  // namespace test
}  // namespace ring_curvature
