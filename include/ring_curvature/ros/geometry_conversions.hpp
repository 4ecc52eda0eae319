// Eigen -> geometry_msgs conversions shared by the message builders (markers, primitives).
#pragma once

#include <geometry_msgs/Point.h>

#include <Eigen/Core>

namespace ring_curvature
{

inline geometry_msgs::Point toPoint(const Eigen::Vector3f& v)
{
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

}  // namespace ring_curvature
