#include "synthetic_scene.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace ring_curvature
{
namespace test
{

namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr float kSensorHeight = 1.8f;  // the ground is z = -kSensorHeight
constexpr float kRoomX = 12.0f, kRoomY = 8.0f, kWallTop = 3.0f;

struct Box
{
  float lo[3], hi[3];
};

/// Entry distance of the ray o + t d into an axis-aligned box (slab method); inf on a miss.
float hitBox(const float d[3], const Box& b)
{
  float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (std::fabs(d[a]) < 1e-9f)
    {
      if (0.0f < b.lo[a] || 0.0f > b.hi[a])
        return std::numeric_limits<float>::infinity();
      continue;
    }
    float ta = b.lo[a] / d[a], tb = b.hi[a] / d[a];
    if (ta > tb)
      std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 && t0 > 0.0f ? t0 : std::numeric_limits<float>::infinity();
}

void put(std::uint8_t* rec, std::size_t off, const void* v, std::size_t n) { std::memcpy(rec + off, v, n); }

constexpr std::uint32_t kStep = 22;  // velodyne's packed XYZIRT record

/// The scene's obstacles: two boxes standing on the ground and the floating sign.
struct Obstacles
{
  Box boxes[3];
  Surface surface[3];
};

Obstacles obstacles(const SceneOptions& o)
{
  return {{
              {{3.0f + o.box_shift, -1.0f, -kSensorHeight}, {5.0f + o.box_shift, 1.0f, -0.3f}},  // box A
              {{-6.0f - o.box_shift, 2.0f, -kSensorHeight}, {-4.0f - o.box_shift, 5.0f, 0.5f}},  // box B
              {{2.0f, -4.15f, 0.0f}, {2.3f, -3.85f, 0.3f}},                                      // floating sign
          },
          {kBoxA, kBoxB, kSign}};
}

/// What a ray from the sensor hits first, at distance t along it (inf on a miss).
struct RayHit
{
  float t;
  Surface surface;
};

RayHit castRay(const float d[3], const Obstacles& obs)
{
  float t = std::numeric_limits<float>::infinity();
  Surface s = kMiss;
  if (d[2] < 0)
  {
    t = -kSensorHeight / d[2];
    s = kGround;
  }
  // The room's walls: the nearest of the four planes in the ray's direction, below the top.
  float tw = std::numeric_limits<float>::infinity();
  if (std::fabs(d[0]) > 1e-9f)
    tw = std::min(tw, (d[0] > 0 ? kRoomX : -kRoomX) / d[0]);
  if (std::fabs(d[1]) > 1e-9f)
    tw = std::min(tw, (d[1] > 0 ? kRoomY : -kRoomY) / d[1]);
  if (tw < t && tw * d[2] < kWallTop)
  {
    t = tw;
    s = kWall;
  }
  for (int b = 0; b < 3; ++b)
  {
    const float tb = hitBox(d, obs.boxes[b]);
    if (tb < t)
    {
      t = tb;
      s = obs.surface[b];
    }
  }
  return {t, s};
}

/// Appends point n, of ring r fired at column k, to f.data.
void appendRecord(SyntheticFrame& f, std::size_t n, const float xyz[3], int r, int k, int columns)
{
  f.data.resize(f.data.size() + kStep);
  std::uint8_t* rec = f.data.data() + n * kStep;
  const float intensity = 10.0f;
  const auto ring = static_cast<std::uint16_t>(r);
  const float time = 0.1f * static_cast<float>(k) / static_cast<float>(columns);
  put(rec, 0, xyz, 12);
  put(rec, 12, &intensity, 4);
  put(rec, 16, &ring, 2);
  put(rec, 18, &time, 4);
}

/// Organized clouds are row = beam: transposes the firing-major records.
void toRows(SyntheticFrame& f, const SceneOptions& o)
{
  std::vector<std::uint8_t> rows(f.data.size());
  std::vector<Surface> srows(f.surface.size());
  for (int k = 0; k < o.columns; ++k)
    for (int r = 0; r < o.rings; ++r)
    {
      const std::size_t from = static_cast<std::size_t>(k) * o.rings + r;
      const std::size_t to = static_cast<std::size_t>(r) * o.columns + k;
      std::memcpy(&rows[to * kStep], &f.data[from * kStep], kStep);
      srows[to] = f.surface[from];
    }
  f.data.swap(rows);
  f.surface.swap(srows);
}

/// Points f.view at f.data, n points in velodyne's layout.
void setView(SyntheticFrame& f, const SceneOptions& o, std::size_t n)
{
  PointCloudView& v = f.view;
  v.data = f.data.data();
  v.data_size = f.data.size();
  v.width = o.organized ? static_cast<std::uint32_t>(o.columns) : static_cast<std::uint32_t>(n);
  v.height = o.organized ? static_cast<std::uint32_t>(o.rings) : 1u;
  v.point_step = kStep;
  v.row_step = kStep * v.width;
  v.x = {0, ScalarType::Float32};
  v.y = {4, ScalarType::Float32};
  v.z = {8, ScalarType::Float32};
  v.intensity = {12, ScalarType::Float32};
  v.ring = {16, ScalarType::UInt16};
  v.time = {18, ScalarType::Float32};
}
}  // namespace

SyntheticFrame makeScene(const SceneOptions& o)
{
  const Obstacles obs = obstacles(o);
  std::mt19937 rng(o.seed);
  std::normal_distribution<float> noise(0.0f, o.range_noise > 0 ? o.range_noise : 1.0f);

  SyntheticFrame f;
  f.data.reserve(static_cast<std::size_t>(o.rings) * o.columns * kStep);
  std::size_t n = 0;
  for (int k = 0; k < o.columns; ++k)
  {
    const float az = 2.0f * kPi * static_cast<float>(k) / static_cast<float>(o.columns);
    for (int r = 0; r < o.rings; ++r)
    {
      const float el_deg = o.rings == 1 ? o.elevation_min_deg
                                        : o.elevation_min_deg + (o.elevation_max_deg - o.elevation_min_deg) *
                                                                    static_cast<float>(r) / static_cast<float>(o.rings - 1);
      const float el = el_deg * kPi / 180.0f;
      const float d[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      const RayHit hit = castRay(d, obs);
      if (hit.surface == kMiss && !o.organized)
        continue;  // an unorganized driver drops misses
      float xyz[3];
      if (hit.surface == kMiss)
        xyz[0] = xyz[1] = xyz[2] = std::numeric_limits<float>::quiet_NaN();
      else
      {
        const float range = hit.t + (o.range_noise > 0 ? noise(rng) : 0.0f);
        for (int a = 0; a < 3; ++a)
          xyz[a] = range * d[a];
      }
      appendRecord(f, n, xyz, r, k, o.columns);
      f.surface.push_back(hit.surface);
      ++n;
      if (!o.organized && o.duplicate_every > 0 && n % static_cast<std::size_t>(o.duplicate_every) == 0)
      {
        f.data.resize(f.data.size() + kStep);
        std::memcpy(f.data.data() + n * kStep, f.data.data() + (n - 1) * kStep, kStep);
        f.surface.push_back(hit.surface);
        ++n;
      }
    }
  }

  if (o.organized)
    toRows(f, o);
  setView(f, o, n);
  return f;
}

}  // namespace test
}  // namespace ring_curvature
