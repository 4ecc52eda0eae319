// A minimal ray caster for core tests: level ground and yaw-rotated boxes seen by a rotating
// multi-beam sensor at the origin. Every return records which object and face it hit, so a
// test can say where along a ring a crease (same box, next face) or a depth jump (another
// object, range changes) lies.
#pragma once

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "synthetic_cloud.hpp"

namespace ring_curvature
{
namespace test
{

struct Box
{
  double cx, cy, z0, z1;  // centre (x, y), bottom and top
  double hx, hy;          // half extents in the box frame
  double yaw;             // rotation about z [rad]
};

struct Hit
{
  double t = std::numeric_limits<double>::infinity();
  int object = -1;  // -1 nothing, 0 ground, 1 + i box i
  int face = -1;
};

struct SensorModel
{
  std::vector<double> elevations;  // [rad] per ring, ring 0 lowest
  double azimuth_step;             // [rad]
  static SensorModel uniform(int beams, double lo_deg, double hi_deg, double step_deg)
  {
    SensorModel s;
    const double d2r = 3.14159265358979323846 / 180;
    for (int i = 0; i < beams; ++i)
      s.elevations.push_back((lo_deg + (beams == 1 ? 0.0 : (hi_deg - lo_deg) * i / (beams - 1))) * d2r);
    s.azimuth_step = step_deg * d2r;
    return s;
  }
};

class RayScene
{
public:
  double ground_z = -1.8;
  std::vector<Box> boxes;

  Hit cast(double dx, double dy, double dz) const
  {
    Hit best;
    if (dz < -1e-9)
    {
      best.t = ground_z / dz;
      best.object = 0;
      best.face = 0;
    }
    for (std::size_t i = 0; i < boxes.size(); ++i)
    {
      const Box& b = boxes[i];
      const double c = std::cos(-b.yaw), s = std::sin(-b.yaw);
      // ray in the box frame (origin at the box centre)
      const double ox = c * (-b.cx) - s * (-b.cy), oy = s * (-b.cx) + c * (-b.cy);
      const double rx = c * dx - s * dy, ry = s * dx + c * dy;
      double tmin = 0, tmax = std::numeric_limits<double>::infinity();
      int face = -1;
      const double o[3] = {ox, oy, 0.0}, r[3] = {rx, ry, dz};
      const double lo[3] = {-b.hx, -b.hy, b.z0}, hi[3] = {b.hx, b.hy, b.z1};
      bool miss = false;
      for (int a = 0; a < 3 && !miss; ++a)
      {
        if (std::fabs(r[a]) < 1e-12)
        {
          miss = o[a] < lo[a] || o[a] > hi[a];
          continue;
        }
        double t0 = (lo[a] - o[a]) / r[a], t1 = (hi[a] - o[a]) / r[a];
        int f0 = 2 * a, f1 = 2 * a + 1;
        if (t0 > t1)
        {
          std::swap(t0, t1);
          std::swap(f0, f1);
        }
        if (t0 > tmin)
        {
          tmin = t0;
          face = f0;
        }
        tmax = std::min(tmax, t1);
        miss = tmin > tmax;
      }
      if (!miss && face >= 0 && tmin < best.t)
      {
        best.t = tmin;
        best.object = 1 + static_cast<int>(i);
        best.face = face;
      }
    }
    return best;
  }
};

/// One scanned frame with its per-point hit record (same order as the cloud).
struct ScannedFrame
{
  SyntheticCloud cloud;
  std::vector<Hit> hits;
  std::vector<int> ring, column;
};

/// Sweeps the sensor over the scene, ring by ring in azimuth order starting at `start` rad;
/// misses become NaN points (as a driver that keeps no-returns would publish).
inline ScannedFrame scan(const RayScene& scene, const SensorModel& s, double noise = 0.0, unsigned seed = 1,
                         double start = 0.0)
{
  ScannedFrame f;
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, noise > 0 ? noise : 1.0);
  const int cols = static_cast<int>(std::lround(2 * 3.14159265358979323846 / s.azimuth_step));
  for (std::size_t n = 0; n < s.elevations.size(); ++n)
    for (int k = 0; k < cols; ++k)
    {
      const double th = start + k * s.azimuth_step;
      double dx, dy, dz;
      beamDir(s.elevations[n], th, dx, dy, dz);
      Hit h = scene.cast(dx, dy, dz);
      if (std::isfinite(h.t) && h.t < 200)
      {
        const double t = h.t + (noise > 0 ? nd(rng) : 0.0);
        f.cloud.add(t * dx, t * dy, t * dz, static_cast<int>(n));
      }
      else
      {
        f.cloud.addNaN(static_cast<int>(n));
        h = Hit{};
      }
      f.hits.push_back(h);
      f.ring.push_back(static_cast<int>(n));
      f.column.push_back(k);
    }
  return f;
}

// A square room seen from inside at its centre: four walls 6 m from the sensor (boxes 12.2 m long,
// 0.2 m thick, from 5 m below it to 5 m above), four creases per ring; ground at `ground_z`.
inline RayScene squareRoom(double ground_z)
{
  RayScene s;
  s.ground_z = ground_z;
  s.boxes.push_back({6.0, 0.0, -5, 5, 0.1, 6.1, 0});
  s.boxes.push_back({-6.0, 0.0, -5, 5, 0.1, 6.1, 0});
  s.boxes.push_back({0.0, 6.0, -5, 5, 6.1, 0.1, 0});
  s.boxes.push_back({0.0, -6.0, -5, 5, 6.1, 0.1, 0});
  return s;
}

}  // namespace test
}  // namespace ring_curvature
