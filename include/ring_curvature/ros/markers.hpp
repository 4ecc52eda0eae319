// rviz markers for the primitives of one frame, and the one label palette shared by the markers,
// config/ring_curvature.rviz and the screenshot checker (test/viz/check_screenshot.py parses
// kLabelPalette from this file, so edit the colours here only).
//
// makePrimitiveMarkers (below) is called by the nodelet once per frame, only while ~markers has
// subscribers.
//
// `cloud` is the same view that was given to Pipeline::process (the primitives' indices point
// into it); the points are read in place to order edge chains and size plane patches.
// The array starts with a DELETEALL, so markers of the previous frame never linger, whatever
// their number, and a restarted nodelet needs no memory of what it drew before.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "ring_curvature/primitives.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{

struct Rgb8
{
  std::uint8_t r, g, b;
};

/// Colour of each Label value (index = label): none grey, plane blue, edge red, corner yellow,
/// rough green. Saturated and far apart so that a screenshot can be checked pixel by pixel.
constexpr std::array<Rgb8, kNumLabels> kLabelPalette = {{
    {150, 150, 150},  // None
    {40, 110, 255},   // Plane
    {255, 30, 30},    // Edge
    {255, 220, 0},    // Corner
    {30, 200, 60},    // Rough
}};

/// Marker namespaces, one per kind, so each can be switched off in rviz's Markers display.
/// A marker's id is the id of its primitive (index in the PrimitiveArray message).
constexpr const char* kPlaneNs = "planes";
constexpr const char* kNormalNs = "plane_normals";
constexpr const char* kEdgeNs = "edges";
constexpr const char* kCornerNs = "corners";
constexpr const char* kRoughNs = "rough";

/// Buffers makePrimitiveMarkers keeps from one call to the next when the caller passes them: they
/// only grow, so a frame allocates none (the points of one primitive at a time, an edge chain
/// being ordered). Their contents between calls mean nothing.
struct MarkerScratch
{
  std::vector<float> x, y, z;
  std::vector<Eigen::Vector3f> chain;
};

/// Plane patches: a TRIANGLE_LIST quad spanning the patch's points in its own plane (centroid,
/// normal = PrimitiveInfo::axis, in-plane principal direction from PrimitiveInfo::covariance,
/// extent from the points) plus an ARROW along the normal. Edge chains: a LINE_STRIP through
/// the points ordered along the edge's axis.
/// Corner clusters and rough clusters: a SPHERE_LIST of their points. Colours: kLabelPalette.
/// Primitives whose indices fall outside `cloud` or whose points are all non-finite are skipped.
/// `reuse`: an array built by an earlier call, filled again when the caller holds its only
/// reference (its markers keep their buffers). `scratch`: buffers kept by the caller for the next
/// call (else allocated for this one).
visualization_msgs::MarkerArrayPtr makePrimitiveMarkers(const PrimitiveSet& prims,
                                                        const PointCloudView& cloud,
                                                        const std_msgs::Header& header,
                                                        visualization_msgs::MarkerArrayPtr reuse = {},
                                                        MarkerScratch* scratch = nullptr);

}  // namespace ring_curvature
