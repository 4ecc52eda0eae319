// The recycled marker slots of a MarkerArray (markers.cpp): markers of an earlier frame filled
// again in place, so that a recycled array allocates nothing for the markers it had. Private to
// ring_curvature_ros; inline, as the slots are taken once per marker.
#pragma once

#include <std_msgs/Header.h>
#include <visualization_msgs/Marker.h>

#include "ring_curvature/primitives.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace ring_curvature
{
namespace detail
{

// Slots::next resets a recycled marker field by field, so it must know every field: these are
// the MD5 sums of the Marker and Header definitions it was written for (a changed definition
// fails here).
static_assert(ros::message_traits::MD5Sum<visualization_msgs::Marker>::static_value1 == 0x4048c9de2a16f4aeULL &&
                  ros::message_traits::MD5Sum<visualization_msgs::Marker>::static_value2 == 0x8e0538085ebf1b97ULL,
              "visualization_msgs/Marker changed: update Slots::next to its fields");
static_assert(ros::message_traits::MD5Sum<std_msgs::Header>::static_value1 == 0x2176decaecbce78aULL &&
                  ros::message_traits::MD5Sum<std_msgs::Header>::static_value2 == 0xbc3b96ef049fabedULL,
              "std_msgs/Header changed: update Slots::next to its fields");

/// Sets `s` to the `n` characters at `v`, leaving it alone when it holds them already: a recycled
/// marker mostly does (the frame id and the namespace of the same slot last frame), and the
/// comparison costs less than the assignment.
inline void setString(std::string& s, const char* v, std::size_t n)
{
  if (s.size() != n || std::memcmp(s.data(), v, n) != 0)
    s.assign(v, n);
}

/// The markers of a frame, filled in order into an array that may hold an earlier frame's: a
/// marker already there is reset to a default one that keeps its buffers (points, strings),
/// so a recycled array allocates nothing for markers it had; the rest is cut off at the end.
struct Slots
{
  std::vector<visualization_msgs::Marker>& markers;
  std::size_t used = 0;
  /// The next marker: a default one with `header` and namespace `ns`.
  visualization_msgs::Marker& next(const std_msgs::Header& header, const char* ns)
  {
    visualization_msgs::Marker& m = used == markers.size() ? markers.emplace_back() : reset(markers[used]);
    ++used;
    m.header.seq = header.seq;
    m.header.stamp = header.stamp;
    setString(m.header.frame_id, header.frame_id.data(), header.frame_id.size());
    setString(m.ns, ns, std::strlen(ns));
    return m;
  }
  /// `m` with every field but the header and the namespace (which next sets) at its default.
  static visualization_msgs::Marker& reset(visualization_msgs::Marker& m)
  {
    // Each field set in place: assigning a default-constructed marker (with the buffers moved
    // out and back around it) would construct and destroy a whole marker each time.
    m.id = 0;
    m.type = 0;
    m.action = 0;
    m.pose = geometry_msgs::Pose();
    m.scale = geometry_msgs::Vector3();
    m.color = std_msgs::ColorRGBA();
    m.lifetime = ros::Duration();
    m.frame_locked = 0;
    m.points.clear();
    m.colors.clear();
    m.text.clear();
    m.mesh_resource.clear();
    m.mesh_use_embedded_materials = 0;
    return m;
  }
};

/// Appends a marker of `prim` to `out` and returns it for the caller to fill in. Built in place:
/// a local marker moved into the array cost a construction, a move and a destruction per marker.
inline visualization_msgs::Marker& addMarker(Slots& out, const std_msgs::Header& header, const char* ns,
                                             const PrimitiveInfo& prim, std::int32_t type)
{
  visualization_msgs::Marker& m = out.next(header, ns);
  m.id = static_cast<std::int32_t>(prim.id);
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;  // points are given in the header's frame
  return m;
}

}  // namespace detail
}  // namespace ring_curvature
