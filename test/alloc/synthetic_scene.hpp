// A ray-cast rotating-LiDAR frame of a known scene, for the allocation and baseline tests:
// ground, the walls of a room, two boxes standing on the ground and a small floating sign.
#pragma once

#include <cstdint>
#include <vector>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{
namespace test
{

/// What a ray hit (ground truth per point).
enum Surface : std::int8_t
{
  kMiss = -1, kGround = 0, kWall = 1, kBoxA = 2, kBoxB = 3, kSign = 4
};

struct SceneOptions
{
  int rings = 16;
  int columns = 1800;          ///< firings per revolution (0.2 deg for 1800)
  float elevation_min_deg = -15.0f, elevation_max_deg = 15.0f;
  bool organized = false;      ///< organized: height = rings, NaN on a miss; else misses dropped
  float range_noise = 0.005f;  ///< [m] 1-sigma Gaussian range noise (fixed seed)
  float box_shift = 0.0f;      ///< [m] moves the boxes along x (different frames, same layout)
  unsigned seed = 1;
  int duplicate_every = 0;     ///< unorganized: every n-th point twice, as a dual return's identical second (0: none)
};

/// One frame in velodyne's packed XYZIRT layout (x, y, z, intensity f32; ring u16; time f32;
/// point_step 22), firing-major like the driver; `view` points into `data`.
struct SyntheticFrame
{
  std::vector<std::uint8_t> data;
  std::vector<Surface> surface;  ///< per point, what was hit
  PointCloudView view;
};

SyntheticFrame makeScene(const SceneOptions& options);

}  // namespace test
}  // namespace ring_curvature
