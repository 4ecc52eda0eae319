// Test clouds: a real frame re-encoded with another ring datatype and field order (same points,
// same geometry), and clouds with one thing wrong, for the adapter and nodelet tests.
#pragma once

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include <boost/make_shared.hpp>
#include <cstring>
#include <string>
#include <vector>

namespace ring_curvature_test
{

/// All PointCloud2 messages on `topic` in a bag.
inline std::vector<sensor_msgs::PointCloud2::ConstPtr> readClouds(const std::string& path, const std::string& topic)
{
  std::vector<sensor_msgs::PointCloud2::ConstPtr> out;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery(topic)))
    if (auto c = m.instantiate<sensor_msgs::PointCloud2>())
      out.push_back(c);
  return out;
}

inline std::size_t typeSize(std::uint8_t t)
{
  static const std::size_t sizes[9] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return t <= 8 ? sizes[t] : 0;
}

/// Re-encodes a velodyne XYZIRT frame (x, y, z, intensity float32, ring uint16, time float32)
/// with `ring_type` for the ring and the fields laid out in the reverse order, padded to
/// 4 bytes. Values are preserved exactly.
inline sensor_msgs::PointCloud2Ptr relayout(const sensor_msgs::PointCloud2& in, std::uint8_t ring_type)
{
  auto out = boost::make_shared<sensor_msgs::PointCloud2>();
  out->header = in.header;
  out->height = in.height;
  out->width = in.width;
  out->is_dense = in.is_dense;
  // reverse order: time, ring, intensity, z, y, x
  std::vector<sensor_msgs::PointField> src(in.fields.rbegin(), in.fields.rend());
  std::uint32_t off = 0;
  for (const auto& f : src)
  {
    sensor_msgs::PointField g = f;
    if (g.name == "ring")
      g.datatype = ring_type;
    g.offset = off;
    g.count = 1;
    off += static_cast<std::uint32_t>((typeSize(g.datatype) + 3) / 4 * 4);
    out->fields.push_back(g);
  }
  out->point_step = off;
  out->row_step = out->point_step * out->width;
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  out->data.assign(n * out->point_step, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t* s = in.data.data() + i * in.point_step;
    std::uint8_t* d = out->data.data() + i * out->point_step;
    for (std::size_t k = 0; k < src.size(); ++k)
    {
      const auto& fi = src[k];
      const auto& fo = out->fields[k];
      if (fi.name != "ring")
      {
        std::memcpy(d + fo.offset, s + fi.offset, typeSize(fi.datatype));
        continue;
      }
      std::uint16_t ring;
      std::memcpy(&ring, s + fi.offset, 2);
      const std::uint8_t r8 = static_cast<std::uint8_t>(ring);
      const std::int16_t r16 = static_cast<std::int16_t>(ring);
      const std::int32_t r32 = ring;
      if (ring_type == sensor_msgs::PointField::UINT8)
        std::memcpy(d + fo.offset, &r8, 1);
      else if (ring_type == sensor_msgs::PointField::INT16)
        std::memcpy(d + fo.offset, &r16, 2);
      else if (ring_type == sensor_msgs::PointField::INT32)
        std::memcpy(d + fo.offset, &r32, 4);
      else
        std::memcpy(d + fo.offset, &ring, 2);
    }
  }
  return out;
}

/// The same cloud with the `ring` field's description removed (bytes unchanged).
inline sensor_msgs::PointCloud2Ptr withoutField(const sensor_msgs::PointCloud2& in, const std::string& name)
{
  auto out = boost::make_shared<sensor_msgs::PointCloud2>(in);
  for (auto it = out->fields.begin(); it != out->fields.end(); ++it)
    if (it->name == name)
    {
      out->fields.erase(it);
      break;
    }
  return out;
}

}  // namespace ring_curvature_test
