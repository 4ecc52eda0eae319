// Cloud outputs built from one FrameResult: the labelled cloud (input + per-point results) and
// the edge / plane landmark clouds in the input's own layout. (The primitive array is built in
// primitive_message.hpp: see there why.)
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include "ring_curvature/pipeline.hpp"

namespace ring_curvature
{

/// Names of the fields appended to the labelled cloud.
constexpr const char* kAppendedFieldNames[5] = {"curvature", "smoothness", "discontinuity", "primitive", "label"};

/// New cloud: every input record copied once, followed by `curvature`, `smoothness`,
/// `discontinuity` (float32), `primitive` (int32) and `label` (uint8), starting at the first
/// 4-byte boundary after the input record; the record is padded to a multiple of 4 bytes.
/// An input field whose name clashes with an appended one is kept, renamed `input_<name>`.
/// Same header, width, height and point order as the input.
/// `reuse`: a cloud built by an earlier call, filled again instead of allocating a new one when
/// the caller holds the only reference left (its buffer keeps its capacity); else ignored.
sensor_msgs::PointCloud2Ptr makeLabelledCloud(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                              sensor_msgs::PointCloud2Ptr reuse = {});

/// New unorganized cloud in the input's layout (every field, time included) holding the input
/// points whose label is `a` or `b`, in input order.
/// (`reuse` as for makeLabelledCloud.)
sensor_msgs::PointCloud2Ptr makeLabelSubset(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                            Label a, Label b, sensor_msgs::PointCloud2Ptr reuse = {});

/// makeLabelledCloud and makeLabelSubset(input, result, Label::Plane, Label::Plane) at once, the
/// same two messages, in one pass over the input: each record is read once for both clouds.
/// `labelled` and `planes` are the reuse candidates on entry (as for those two) and the new
/// messages on return.
void makeLabelledAndPlaneClouds(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                sensor_msgs::PointCloud2Ptr& labelled, sensor_msgs::PointCloud2Ptr& planes);

}  // namespace ring_curvature
