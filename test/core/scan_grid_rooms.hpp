// The rooms the scan grid tests scan (test_scan_grid.cpp, test_scan_grid_dual_returns.cpp).
#pragma once

#include "../support/ray_scene.hpp"

namespace ring_curvature
{
namespace test
{

// The square room (ray_scene.hpp) without ground: the ground at -100 m is out of range, so the
// rings stay on the walls.
inline RayScene room() { return squareRoom(-100); }

// The room standing on level ground, 16 beams, 5 mm noise: walls, creases, ground, jumps.
inline ScannedFrame roomOnGround()
{
  RayScene s = room();
  s.ground_z = -1.8;
  return scan(s, SensorModel::uniform(16, -15, 15, 0.2), 0.005, 3);
}

}  // namespace test
}  // namespace ring_curvature
