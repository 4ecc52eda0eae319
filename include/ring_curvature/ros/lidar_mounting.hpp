// Where the LiDAR sits in the frame an odometry reports (e.g. base_link), from tf: deskewing needs
// the LiDAR's own motion, and a base's motion differs from it wherever the base turns.
#pragma once

#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <string>

namespace ring_curvature
{

class LidarMounting
{
public:
  /// Listens to /tf and /tf_static through `nh` (its callback queue: the nodelet manager's).
  explicit LidarMounting(ros::NodeHandle& nh);
  /// The pose of frame `lidar` (the cloud's) in frame `child` (the odometry's), leading '/' ignored;
  /// the identity when they are the same frame. Looked up once per pair of frames (a mounting is
  /// static); false, with `error` naming the frames and tf's reason, while tf does not have it.
  bool lidarInChild(const std::string& child, const std::string& lidar, Eigen::Isometry3d& pose, std::string& error);

private:
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  std::string child_, lidar_;  // the pair pose_ belongs to
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  bool have_ = false;
};

}  // namespace ring_curvature
