// The sensor's motion per sweep from an odometry topic (e.g. the back end's own): the mean motion
// over the last `window` seconds of poses, scaled to one sweep, is the constant-velocity model the
// LOAM clouds are deskewed with. Averaged because a back end that matches scan to scan sees the
// difference between two frames' deskews: fed back frame by frame, that difference oscillates.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/time.h>

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <mutex>
#include <string>

#include "ring_curvature/sweep_deskew.hpp"

namespace ring_curvature
{

class OdometryMotion
{
public:
  /// A pose of the odometry's child frame (the LiDAR's, or one it is mounted on) in a fixed frame.
  void add(const nav_msgs::Odometry& odom);
  /// The mean motion over one sweep of `period` s, from the newest pose and the oldest one at most
  /// `window` s before it; false (no deskew) before two poses or when the newest is more than
  /// `max_age` s from `stamp`. `lidar_in_child`: the LiDAR's pose in the child frame (its
  /// mounting); null when the child frame is the LiDAR's.
  bool motionFor(const ros::Time& stamp, double period, double window, double max_age, SweepMotion& motion,
                 const Eigen::Isometry3d* lidar_in_child = nullptr) const;
  /// The child frame of the newest pose as the odometry names it (empty before any), into `out`
  /// (assigned in place: no allocation per frame once it has the room).
  void childFrame(std::string& out) const;

private:
  struct Pose
  {
    ros::Time stamp;
    Eigen::Quaterniond q;
    Eigen::Vector3d p;
  };
  mutable std::mutex mutex_;  // odometry and clouds arrive on different callback threads
  static constexpr std::size_t kHistory = 64;  // poses kept (6 s at 10 Hz)
  std::array<Pose, kHistory> poses_;            // a ring: newest at (head_ + count_ - 1) % kHistory
  std::size_t head_ = 0, count_ = 0;
  std::string child_frame_;
};

}  // namespace ring_curvature
