// Synthetic clouds as sensor_msgs/PointCloud2, for the adapter-level robustness tests and the
// fuzz target (sensor_msgs message types are header-only structs: no ROS master needed).
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <string>

#include "synthetic_cloud.hpp"

namespace ring_curvature
{
namespace test
{

inline void addField(sensor_msgs::PointCloud2& msg, const std::string& name, const FieldView& f)
{
  if (!f.present())
    return;
  sensor_msgs::PointField pf;
  pf.name = name;
  pf.offset = static_cast<std::uint32_t>(f.offset);
  pf.datatype = static_cast<std::uint8_t>(f.type);
  pf.count = 1;
  msg.fields.push_back(pf);
}

/// The cloud as a message, fields named as velodyne_pointcloud names them.
inline sensor_msgs::PointCloud2 toMsg(const Cloud& c, const std::string& time_name = "time")
{
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = "velodyne";
  msg.header.stamp.sec = 1700000000;
  msg.width = c.width;
  msg.height = c.height;
  msg.point_step = c.point_step;
  msg.row_step = c.row_step;
  msg.is_bigendian = false;
  msg.is_dense = false;
  addField(msg, "x", c.layout.x);
  addField(msg, "y", c.layout.y);
  addField(msg, "z", c.layout.z);
  addField(msg, "intensity", c.layout.intensity);
  addField(msg, "ring", c.layout.ring);
  addField(msg, time_name, c.layout.time);
  msg.data = c.data;
  return msg;
}

inline sensor_msgs::PointField* field(sensor_msgs::PointCloud2& msg, const std::string& name)
{
  for (auto& f : msg.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

}  // namespace test
}  // namespace ring_curvature
