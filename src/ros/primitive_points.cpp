// A plane patch's frame for its marker (primitive_points.hpp): once per plane, not per point.

#include "primitive_points.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace ring_curvature
{
namespace
{

/// A unit vector perpendicular to n (n need not be normalised).
Eigen::Vector3f anyPerpendicular(const Eigen::Vector3f& n)
{
  const Eigen::Vector3f helper =
      std::abs(n.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  return n.cross(helper).normalized();
}

}  // namespace

namespace detail
{

bool planeFrame(const PrimitiveInfo& prim, PlaneFrame& f)
{
  Eigen::Vector3f n = prim.axis;
  if (!(n.squaredNorm() > 0.0f) || !n.allFinite())
    return false;
  n.normalize();
  f.n = n;
  // In-plane principal direction from the points' 2-D covariance, so the quad follows the patch
  // (a wall strip seen by 16 rings is long and thin; a square would misdraw it).
  const Eigen::Vector3f u0 = anyPerpendicular(n), v0 = n.cross(u0);
  f.cx = prim.centroid.x();
  f.cy = prim.centroid.y();
  f.cz = prim.centroid.z();
  const Eigen::Matrix3f& c = prim.covariance;
  const Eigen::Vector3f cu = c * u0, cv = c * v0;
  const float cuu = u0.dot(cu), cvv = v0.dot(cv), cuv = u0.dot(cv);
  // Major axis of a 2x2 covariance in closed form (no iterative solver for two dimensions).
  const float angle = 0.5f * std::atan2(2.0f * cuv, cuu - cvv);
  f.u = (std::cos(angle) * u0 + std::sin(angle) * v0).normalized();
  f.v = n.cross(f.u);
  return true;
}

}  // namespace detail
}  // namespace ring_curvature
