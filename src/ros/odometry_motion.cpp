#include "ring_curvature/ros/odometry_motion.hpp"

#include <algorithm>
#include <cmath>

namespace ring_curvature
{

void OdometryMotion::add(const nav_msgs::Odometry& odom)
{
  const auto& o = odom.pose.pose.orientation;
  const auto& t = odom.pose.pose.position;
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  if (!std::isfinite(q.norm()) || q.norm() < 0.5 || !std::isfinite(t.x + t.y + t.z)) return;  // not a pose
  std::lock_guard<std::mutex> lock(mutex_);
  if (odom.child_frame_id != child_frame_) child_frame_ = odom.child_frame_id;
  // the same stamp again: a refined pose of that frame; time going back (a bag played again, a
  // restarted back end): the history is another run's
  const Pose pose{odom.header.stamp, q.normalized(), Eigen::Vector3d(t.x, t.y, t.z)};
  Pose* const newest = count_ > 0 ? &poses_[(head_ + count_ - 1) % kHistory] : nullptr;
  if (newest && pose.stamp == newest->stamp)
  {
    *newest = pose;
    return;
  }
  if (newest && pose.stamp < newest->stamp) count_ = 0;
  if (count_ == kHistory) head_ = (head_ + 1) % kHistory;
  else ++count_;
  poses_[(head_ + count_ - 1) % kHistory] = pose;
}

void OdometryMotion::childFrame(std::string& out) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  out.assign(child_frame_);
}

bool OdometryMotion::motionFor(const ros::Time& stamp, double period, double window, double max_age,
                               SweepMotion& motion, const Eigen::Isometry3d* lidar_in_child) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ < 2) return false;
  const Pose& newer = poses_[(head_ + count_ - 1) % kHistory];
  if (std::fabs((stamp - newer.stamp).toSec()) > max_age) return false;
  std::size_t k = count_ - 2;  // the oldest pose within the window (at least the one before)
  while (k > 0 && (newer.stamp - poses_[(head_ + k - 1) % kHistory].stamp).toSec() <= window) --k;
  const Pose& older = poses_[(head_ + k) % kHistory];
  const double dt = (newer.stamp - older.stamp).toSec();
  if (dt <= 0.0 || dt > std::max(window, max_age)) return false;
  // the newer pose in the older one's frame: the motion over dt in the sensor's own frame
  Eigen::Quaterniond dq = older.q.conjugate() * newer.q;
  Eigen::Vector3d dp = older.q.conjugate() * (newer.p - older.p);
  if (lidar_in_child)
  {
    // the LiDAR's own motion: E^-1 * (dq, dp) * E, with E its pose in the child frame
    const Eigen::Quaterniond e(lidar_in_child->rotation());
    const Eigen::Vector3d te = lidar_in_child->translation();
    dp = e.conjugate() * (dq * te + dp - te);
    dq = e.conjugate() * dq * e;
  }
  const Eigen::AngleAxisd aa(dq);
  const double scale = period / dt;
  const Eigen::Vector3d w = aa.axis() * (aa.angle() * scale), v = dp * scale;
  for (std::size_t i = 0; i < 3; ++i)
  {
    motion.rotation[i] = w[static_cast<Eigen::Index>(i)];
    motion.translation[i] = v[static_cast<Eigen::Index>(i)];
  }
  return true;
}

}  // namespace ring_curvature
