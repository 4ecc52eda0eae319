// The subset clouds' layout, shared by makeLabelSubset (label_subsets.cpp) and the one-pass
// labelled and plane clouds (outputs.cpp). Private to ring_curvature_ros.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include "ring_curvature/pipeline.hpp"

#include <cstddef>
#include <cstdint>

namespace ring_curvature
{
namespace detail
{

// Everything of a subset cloud (points labelled a or b) but its records (sized, not filled).
// Returns the number of points.
std::size_t subsetLayout(const sensor_msgs::PointCloud2& input, const FrameResult& result, std::uint8_t a,
                         std::uint8_t b, sensor_msgs::PointCloud2& cloud);

}  // namespace detail
}  // namespace ring_curvature
