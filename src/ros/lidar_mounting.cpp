#include "ring_curvature/ros/lidar_mounting.hpp"

namespace ring_curvature
{

namespace
{
std::size_t slash(const std::string& frame) { return !frame.empty() && frame[0] == '/' ? 1 : 0; }
std::string bare(const std::string& frame) { return frame.substr(slash(frame)); }
// `frame` names `bare_name` (checked per cloud: no copy)
bool names(const std::string& frame, const std::string& bare_name)
{
  return frame.compare(slash(frame), std::string::npos, bare_name) == 0;
}
}  // namespace

LidarMounting::LidarMounting(ros::NodeHandle& nh) : listener_(buffer_, nh, false) {}

bool LidarMounting::lidarInChild(const std::string& child, const std::string& lidar, Eigen::Isometry3d& pose,
                                 std::string& error)
{
  if (have_ && names(child, child_) && names(lidar, lidar_))
  {
    pose = pose_;
    return true;
  }
  have_ = false;
  const std::string c = bare(child), l = bare(lidar);
  if (c.empty() || c == l)
  {
    pose_ = Eigen::Isometry3d::Identity();
  }
  else
  {
    geometry_msgs::TransformStamped t;
    try
    {
      // target child, source lidar: maps LiDAR coordinates into the child frame, i.e. the LiDAR's pose there
      t = buffer_.lookupTransform(c, l, ros::Time(0));
    }
    catch (const tf2::TransformException& e)
    {
      error = "no transform from the odometry's child frame '" + c + "' to the cloud's frame '" + l +
              "' in tf: " + e.what();
      return false;
    }
    const auto& q = t.transform.rotation;
    const auto& p = t.transform.translation;
    pose_ = Eigen::Isometry3d::Identity();
    pose_.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
    pose_.translation() = Eigen::Vector3d(p.x, p.y, p.z);
  }
  child_ = c;
  lidar_ = l;
  have_ = true;
  pose = pose_;
  return true;
}

}  // namespace ring_curvature
