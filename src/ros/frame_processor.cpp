#include "ring_curvature/ros/frame_processor.hpp"

#include <chrono>
#include <vector>

#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/markers.hpp"
#include "ring_curvature/ros/outputs.hpp"

namespace ring_curvature
{

struct FrameProcessor::Impl
{
  explicit Impl(const Params& p) : pipeline(p) {}
  Pipeline pipeline;
  FrameResult result;
  // The messages of the last frame, recycled for the next one once the subscribers have dropped
  // them (ros/recycle.hpp): a new 0.6 MB labelled cloud a frame was allocated, zero-filled and
  // freed again, and the markers and primitives were a thousand small allocations.
  sensor_msgs::PointCloud2Ptr labelled, edges, planes;
  PrimitiveArrayPtr primitives;
  visualization_msgs::MarkerArrayPtr markers;
  MarkerScratch marker_scratch;  // (grown to the largest primitive once, not allocated per frame)
};

FrameProcessor::FrameProcessor(const Params& params) : impl_(std::make_unique<Impl>(params)) {}
FrameProcessor::~FrameProcessor() = default;

Status FrameProcessor::setParams(const Params& params) { return impl_->pipeline.setParams(params); }
const Params& FrameProcessor::params() const { return impl_->pipeline.params(); }
const FrameResult& FrameProcessor::result() const { return impl_->result; }

Status FrameProcessor::process(const sensor_msgs::PointCloud2& msg, Outputs& out, const OutputSelection& select)
{
  out = Outputs();
  PointCloudView view;
  Status s = makeView(msg, impl_->pipeline.params(), view);
  if (!s)
    return s;
  last_input_data_ = view.data;
  FrameResult& r = impl_->result;
  s = impl_->pipeline.process(view, r);
  if (!s)
    return s;

  const auto t0 = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  // The plane cloud is built with the labelled one when both are wanted: one pass over the input.
  if (select.labelled && select.planes)
  {
    makeLabelledAndPlaneClouds(msg, r, m.labelled, m.planes);
    out.labelled = m.labelled;
    out.planes = m.planes;
  }
  else if (select.labelled)
    out.labelled = m.labelled = makeLabelledCloud(msg, r, std::move(m.labelled));
  else if (select.planes)
    out.planes = m.planes = makeLabelSubset(msg, r, Label::Plane, Label::Plane, std::move(m.planes));
  if (select.primitives)
  {
    out.primitives = m.primitives = makePrimitiveArray(msg.header, r.primitives, std::move(m.primitives));
  }
  if (select.edges)
    out.edges = m.edges = makeLabelSubset(msg, r, Label::Edge, Label::Corner, std::move(m.edges));
  if (select.markers)
    out.markers = m.markers = makePrimitiveMarkers(r.primitives, view, msg.header, std::move(m.markers), &m.marker_scratch);

  FrameSummary& f = summary_;
  f.points = r.label.size();
  f.label_counts = r.label_counts;
  f.primitives = r.primitives.primitives.size();
  f.grid_ms = r.times.grid;
  f.features_ms = r.times.features;
  f.thresholds_ms = r.times.thresholds;
  f.classification_ms = r.times.classification;
  f.primitives_ms = r.times.primitives;
  f.core_output_ms = r.times.output;
  f.messages_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return Status::success();
}

}  // namespace ring_curvature
