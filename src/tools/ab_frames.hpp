// The bag's frames as ab_core hands them to both builds: the messages read once, and each one
// described in the shim's plain C layout (RcAbCloud) over the message's own bytes.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <string>
#include <vector>

#include "ab_shim.h"

namespace ring_curvature
{
namespace ab
{

/// The little-endian PointCloud2 frames on `topic` (every such topic if empty). False, with the
/// reason on stderr, when the bag cannot be read or holds none.
bool readFrames(const std::string& bag, const std::string& topic,
                std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds);

/// The field layout as the nodelet's adapter (makeView) finds it with default parameters: x, y,
/// z, the first present name of ring_field and of time_field, intensity. The core checks the
/// rest. Points into `msg`'s data, which must outlive it.
RcAbCloud toCloud(const sensor_msgs::PointCloud2& msg);

}  // namespace ab
}  // namespace ring_curvature
