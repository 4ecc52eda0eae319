// Primitives of one frame as rviz markers (see markers.hpp for the shapes and the palette). The
// points are read by primitive_points.hpp, the markers taken from marker_slots.hpp.

#include "ring_curvature/ros/markers.hpp"
#include "marker_slots.hpp"
#include "primitive_points.hpp"
#include "ring_curvature/ros/geometry_conversions.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <Eigen/Geometry>
#include <boost/make_shared.hpp>
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace ring_curvature
{
namespace
{

using detail::addMarker;
using detail::PlaneExtents;
using detail::Points;
using detail::Slots;

// Sizes in metres: thick enough to read at the 10-30 m scale of a VLP-16 scene in rviz.
constexpr double kEdgeLineWidth = 0.05;
constexpr double kCornerSphere = 0.15;
constexpr double kRoughSphere = 0.08;
constexpr double kNormalShaft = 0.03;
constexpr float kNormalMinLength = 0.3f, kNormalMaxLength = 1.0f;
constexpr float kPlaneAlpha = 0.6f;  // see-through, so the labelled points under it stay visible

std_msgs::ColorRGBA colourOf(Label label, float alpha)
{
  const Rgb8 c = kLabelPalette[static_cast<std::size_t>(label)];
  std_msgs::ColorRGBA out;
  out.r = static_cast<float>(c.r) / 255.0f;
  out.g = static_cast<float>(c.g) / 255.0f;
  out.b = static_cast<float>(c.b) / 255.0f;
  out.a = alpha;
  return out;
}

/// `ext`: the patch's extents (pointsOf into PlaneExtents, merged).
void addPlane(const PrimitiveInfo& prim, const PlaneExtents& ext, const std_msgs::Header& header, Slots& out)
{
  const Eigen::Vector3f& n = ext.f.n;
  const Eigen::Vector3f& u = ext.f.u;
  const Eigen::Vector3f& v = ext.f.v;
  float umin = ext.umin, umax = ext.umax, vmin = ext.vmin, vmax = ext.vmax;
  // A single-ring patch has no extent across the ring: give it a sliver so it is still drawn.
  const float min_half = 0.02f;
  vmin = std::min(vmin, -min_half);
  vmax = std::max(vmax, min_half);
  umin = std::min(umin, -min_half);
  umax = std::max(umax, min_half);
  const Eigen::Vector3f c = prim.centroid;
  const Eigen::Vector3f a = c + umin * u + vmin * v, b = c + umax * u + vmin * v,
                        d = c + umax * u + vmax * v, e = c + umin * u + vmax * v;

  auto& quad = addMarker(out, header, kPlaneNs, prim, visualization_msgs::Marker::TRIANGLE_LIST);
  quad.scale.x = quad.scale.y = quad.scale.z = 1.0;
  quad.color = colourOf(Label::Plane, kPlaneAlpha);
  // Both windings: rviz culls and darkens back faces, and the patch is seen from either side.
  quad.points.reserve(12);
  for (const auto* corner : {&a, &b, &d, &a, &d, &e, &a, &d, &b, &a, &e, &d})
    quad.points.push_back(toPoint(*corner));

  const float size = std::max(umax - umin, vmax - vmin);
  const float length = std::clamp(0.5f * size, kNormalMinLength, kNormalMaxLength);
  auto& arrow = addMarker(out, header, kNormalNs, prim, visualization_msgs::Marker::ARROW);
  arrow.scale.x = kNormalShaft;        // shaft diameter
  arrow.scale.y = 2.0 * kNormalShaft;  // head diameter
  arrow.scale.z = 3.0 * kNormalShaft;  // head length
  arrow.color = colourOf(Label::Plane, 1.0f);
  arrow.points.reserve(2);
  arrow.points.push_back(toPoint(c));
  arrow.points.push_back(toPoint(c + length * n));
}

void addEdge(const PrimitiveInfo& prim, const Points& chain, const std_msgs::Header& header,
             std::vector<Eigen::Vector3f>& pts, Slots& out)
{
  if (chain.size < 2)
    return;
  pts.resize(chain.size);  // (a buffer kept between edges and frames)
  for (std::size_t k = 0; k < chain.size; ++k)
    pts[k] = chain[k];
  // Grid order is ring-major, not along the edge; ordering by position on the principal axis
  // gives one clean stroke for both vertical (across rings) and along-ring chains.
  Eigen::Vector3f axis = prim.axis;
  if (!(axis.squaredNorm() > 0.0f) || !axis.allFinite())
    axis = pts.back() - pts.front();
  const Eigen::Vector3f c = prim.centroid;
  std::sort(pts.begin(), pts.end(), [&](const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
    return (p - c).dot(axis) < (q - c).dot(axis);
  });
  auto& line = addMarker(out, header, kEdgeNs, prim, visualization_msgs::Marker::LINE_STRIP);
  line.scale.x = kEdgeLineWidth;
  line.color = colourOf(Label::Edge, 1.0f);
  line.points.reserve(pts.size());
  for (const auto& p : pts)
    line.points.push_back(toPoint(p));
}

void addCluster(const PrimitiveInfo& prim, const Points& pts, const std_msgs::Header& header, const char* ns,
                double diameter, Slots& out)
{
  auto& spheres = addMarker(out, header, ns, prim, visualization_msgs::Marker::SPHERE_LIST);
  spheres.scale.x = spheres.scale.y = spheres.scale.z = diameter;
  spheres.color = colourOf(prim.label, 1.0f);
  spheres.points.reserve(pts.size);
  for (std::size_t k = 0; k < pts.size; ++k)
    spheres.points.push_back(toPoint(pts[k]));
}

}  // namespace

visualization_msgs::MarkerArrayPtr makePrimitiveMarkers(const PrimitiveSet& prims,
                                                        const PointCloudView& cloud,
                                                        const std_msgs::Header& header,
                                                        visualization_msgs::MarkerArrayPtr reuse,
                                                        MarkerScratch* scratch)
{
  MarkerScratch local;
  MarkerScratch& buf = scratch != nullptr ? *scratch : local;
  auto array = recycled(std::move(reuse));
  array->markers.reserve(2 * prims.primitives.size() + 1);
  Slots out{array->markers};
  visualization_msgs::Marker& clear = out.next(header, "");
  clear.action = visualization_msgs::Marker::DELETEALL;

  for (const PrimitiveInfo& prim : prims.primitives)
  {
    if (prim.label == Label::Plane)
    {
      PlaneExtents extents;
      if (!detail::planeFrame(prim, extents.f))
        continue;
      if (detail::pointsOf(prims, prim, cloud, extents) > 0)
      {
        extents.merge();
        addPlane(prim, extents, header, out);
      }
      continue;
    }
    const Points pts = detail::storedPoints(prims, prim, cloud, buf);
    if (pts.size == 0)
      continue;
    switch (prim.label)
    {
      case Label::Plane:  // (above)
        break;
      case Label::Edge:
        addEdge(prim, pts, header, buf.chain, out);
        break;
      case Label::Corner:
        addCluster(prim, pts, header, kCornerNs, kCornerSphere, out);
        break;
      case Label::Rough:
        addCluster(prim, pts, header, kRoughNs, kRoughSphere, out);
        break;
      case Label::None:
        break;
    }
  }
  array->markers.resize(out.used);  // (only ever shrinks: no default markers are added)
  return array;
}

}  // namespace ring_curvature
