#include "ab_frames.hpp"

#include <cstdint>
#include <exception>
#include <iostream>
#include <string_view>

#include "bag_clouds.hpp"
#include "ring_curvature/params.hpp"  // the default field lists (header-only use: nothing to link)

namespace ring_curvature
{
namespace ab
{
namespace
{

std::uint8_t fieldType(const sensor_msgs::PointCloud2& msg, const char* name, std::int64_t& offset)
{
  for (const auto& f : msg.fields)
    if (f.name == name)
    {
      offset = f.offset;
      return f.datatype;
    }
  offset = -1;
  return 7;  // float32, unused for an absent field
}

// The first field of a comma-separated list that the cloud has, as the adapter picks it.
RcAbField firstField(const sensor_msgs::PointCloud2& msg, const std::string& names)
{
  RcAbField f{};
  f.offset = -1;
  ring_curvature::forEachFieldName(names, [&](std::string_view name) {
    f.type = fieldType(msg, std::string(name).c_str(), f.offset);
    return f.offset >= 0;
  });
  return f;
}

}  // namespace

bool readFrames(const std::string& bag, const std::string& topic,
                std::vector<sensor_msgs::PointCloud2::ConstPtr>& clouds)
{
  try
  {
    for (auto& c : bench::readClouds(bag, topic))
      if (!c->is_bigendian)  // the shim reads little-endian records only
        clouds.push_back(std::move(c));
  }
  catch (const std::exception& e)
  {
    std::cerr << "ab_core: cannot read " << bag << ": " << e.what() << "\n";
    return false;
  }
  if (clouds.empty())
    std::cerr << "ab_core: no usable PointCloud2 frames in " << bag << "\n";
  return !clouds.empty();
}

RcAbCloud toCloud(const sensor_msgs::PointCloud2& msg)
{
  static const ring_curvature::Params defaults;
  RcAbCloud c{};
  c.data = msg.data.data();
  c.data_size = msg.data.size();
  c.width = msg.width;
  c.height = msg.height;
  c.point_step = msg.point_step;
  c.row_step = msg.row_step;
  c.x.type = fieldType(msg, "x", c.x.offset);
  c.y.type = fieldType(msg, "y", c.y.offset);
  c.z.type = fieldType(msg, "z", c.z.offset);
  c.ring = firstField(msg, defaults.ring_field);
  c.intensity.type = fieldType(msg, "intensity", c.intensity.offset);
  c.time = firstField(msg, defaults.time_field);
  return c;
}

}  // namespace ab
}  // namespace ring_curvature
