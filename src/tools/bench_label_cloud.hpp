// Writes a labelled copy of an input cloud: every input field, plus `label` (uint8), the layout
// /ring_curvature/labelled_points uses, so that baseline labels are scored like ours.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <vector>

namespace ring_curvature
{
namespace bench
{

/// `out` = `in` with a uint8 field `label` appended to every record (same width, height, header,
/// organisation). `labels` holds width * height entries in input order. An existing `label`
/// field in `in` is replaced, not duplicated.
void appendLabelField(const sensor_msgs::PointCloud2& in, const std::vector<std::uint8_t>& labels,
                      sensor_msgs::PointCloud2& out);

}  // namespace bench
}  // namespace ring_curvature
