// sensor_msgs/PointCloud2 -> PointCloudView: fields looked up by name and checked by datatype,
// layout checked against the message's sizes, read in place (no copy of the point data).
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <string>

#include "ring_curvature/params.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{

/// Fills `view` with pointers into `msg.data` (the view is only valid while `msg` lives).
/// Checks what is ROS-specific: endianness, field names and datatypes, field extents against
/// point_step, row_step against width * point_step, data.size() against row_step * height.
/// The ring and time are the first fields named in params.ring_field / params.time_field that
/// the cloud has; view.time_scale follows params.time_unit ("auto": float fields seconds, or
/// nanoseconds above 1e12; integer fields nanoseconds).
/// On error the message names the problem and what to do about it.
/// @param[in] msg     the cloud, read in place
/// @param[in] params  ring_field, time_field, time_unit; ring_from_elevation decides whether a
///                    missing ring field is an error
/// @param[out] view   valid only on success
Status makeView(const sensor_msgs::PointCloud2& msg, const Params& params, PointCloudView& view);

/// Comma-separated "name:type" list of the message's fields, for error messages.
std::string describeFields(const sensor_msgs::PointCloud2& msg);

}  // namespace ring_curvature
