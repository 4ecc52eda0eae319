// The PointCloud2 frames of a bag as the lab's tools pick them: those on one topic, or, when no
// topic is named, those of every topic of that type.
#pragma once

#include <rosbag/bag.h>
#include <rosbag/query.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include <string>
#include <vector>

namespace ring_curvature
{
namespace bench
{

/// Adds to `view` the messages on `topic`, or every sensor_msgs/PointCloud2 if `topic` is empty.
inline void addCloudQuery(rosbag::View& view, const rosbag::Bag& bag, const std::string& topic)
{
  if (topic.empty())
    view.addQuery(bag, rosbag::TypeQuery("sensor_msgs/PointCloud2"));
  else
    view.addQuery(bag, rosbag::TopicQuery(topic));
}

/// Every PointCloud2 that addCloudQuery picks from the bag at `path`, in bag order (messages of
/// other types on `topic` are left out). Throws what rosbag throws.
inline std::vector<sensor_msgs::PointCloud2::ConstPtr> readClouds(const std::string& path, const std::string& topic)
{
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view;
  addCloudQuery(view, bag, topic);
  for (const rosbag::MessageInstance& m : view)
    if (auto c = m.instantiate<sensor_msgs::PointCloud2>())
      clouds.push_back(c);
  return clouds;
}

}  // namespace bench
}  // namespace ring_curvature
