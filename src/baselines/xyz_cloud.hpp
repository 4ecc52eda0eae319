// The input of the PCL baselines: the valid returns of a core PointCloudView as a PCL cloud,
// with the map back to the input point index, so baseline labels line up with ours point for point.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <vector>

#include "ring_curvature/types.hpp"

namespace ring_curvature
{
namespace baselines
{

/// Which returns the baselines see: the same validity rule as the core's scan grid (finite, range
/// within [min_range, max_range]) so that both label the same points.
struct ValidRange
{
  float min_range = 0.3f;    ///< [m] same default as Params::min_range
  float max_range = 250.0f;  ///< [m] same default as Params::max_range
};

/// Valid points of a view, packed; `index[i]` is the input index of `cloud->points[i]`.
struct XyzCloud
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
  std::vector<std::uint32_t> index;
};

/// Reads x, y, z of every point in place (Float32 or Float64, unaligned) and keeps the valid ones.
void fillXyzCloud(const PointCloudView& view, const ValidRange& range, XyzCloud& out);

}  // namespace baselines
}  // namespace ring_curvature
