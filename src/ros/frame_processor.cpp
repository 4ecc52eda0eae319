#include "ring_curvature/ros/frame_processor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "ring_curvature/pipeline.hpp"
#include "ring_curvature/ros/cloud_adapter.hpp"
#include "ring_curvature/ros/loam_outputs.hpp"
#include "ring_curvature/ros/markers.hpp"
#include "ring_curvature/ros/outputs.hpp"

namespace ring_curvature
{

namespace
{
/// Seconds from the sweep's first point to the header stamp, in [0, period]: the time the deskewed
/// points refer to, so that a pose a back end stamps with it is the sensor's at that time. Relative
/// time fields count from the stamp (Velodyne's run up to it, Ouster's from it), absolute ones
/// (Hesai, RoboSense) are compared with it; without a time field the sweep starts at the stamp.
double stampInSweep(const ros::Time& stamp, const LoamFeatures& loam, double period)
{
  if (!loam.time_from_field) return 0.0;
  const bool absolute = std::fabs(loam.first_time) > 1e6;  // (an epoch in seconds, not an offset)
  const double t = absolute ? stamp.toSec() - loam.first_time : -loam.first_time;
  return std::min(std::max(t, 0.0), period);
}
}  // namespace

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
  LoamFeatures loam;
  sensor_msgs::PointCloud2Ptr loam_cloud, sharp, less_sharp, flat, less_flat;
  bool deskew = false, middle = false;
  SweepMotion motion;
  SweepDeskew deskewer;
};

FrameProcessor::FrameProcessor(const Params& params) : impl_(std::make_unique<Impl>(params)) {}
FrameProcessor::~FrameProcessor() = default;

Status FrameProcessor::setParams(const Params& params) { return impl_->pipeline.setParams(params); }
const Params& FrameProcessor::params() const { return impl_->pipeline.params(); }
const FrameResult& FrameProcessor::result() const { return impl_->result; }

void FrameProcessor::setSweepMotion(const SweepMotion* motion)
{
  impl_->deskew = motion != nullptr;
  if (motion) impl_->motion = *motion;
}

void FrameProcessor::setSweepMiddleReference(bool on) { impl_->middle = on; }

Status FrameProcessor::process(const sensor_msgs::PointCloud2& msg, Outputs& out, const OutputSelection& select)
{
  out = Outputs();
  PointCloudView view;
  Status s = makeView(msg, impl_->pipeline.params(), view);
  if (!s)
    return s;
  last_input_data_ = view.data;
  FrameResult& r = impl_->result;
  // Primitives and the per-point arrays in input order serve only the label outputs.
  const bool labels_out = select.labelled || select.primitives || select.edges || select.planes || select.markers;
  s = impl_->pipeline.process(view, r, labels_out || !select.anyLoam() ? Pipeline::Scope::Full : Pipeline::Scope::GridLabels);
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
  f.loam = select.anyLoam();
  f.loam_ms = 0;
  f.deskewed = false;
  if (f.loam)
  {
    const auto tl = std::chrono::steady_clock::now();
    m.pipeline.selectLoamFeatures(view, m.loam);
    f.loam_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tl).count();
    const ScanGrid& g = m.pipeline.grid();
    const Params& P = m.pipeline.params();
    const LoamPointFormat fmt = P.loam_point_format;
    // (the input format copies the records: its points stay as the sensor gave them)
    f.deskewed = m.deskew && fmt == LoamPointFormat::Xyzi;
    const double at_stamp = stampInSweep(msg.header.stamp, m.loam, P.scan_period);
    const bool middle = m.middle && fmt == LoamPointFormat::Xyzi;
    const double reference = middle ? 0.5 * P.scan_period : at_stamp;
    if (f.deskewed) m.deskewer.prepare(m.motion, P.scan_period, reference);
    const SweepDeskew* dk = f.deskewed ? &m.deskewer : nullptr;
    // (a stamp that would fall before the epoch, from a zero stamp, stays: ros::Time throws there)
    const ros::Duration shift(reference - at_stamp);
    const bool restamp = middle && msg.header.stamp.toSec() + shift.toSec() >= 0.0;
    const ros::Time stamp = restamp ? msg.header.stamp + shift : msg.header.stamp;
    const auto cloud = [&](const std::vector<std::uint32_t>* set, sensor_msgs::PointCloud2Ptr& keep) {
      keep = makeLoamCloud(msg, g, m.loam, set, fmt, std::move(keep), dk);
      keep->header.stamp = stamp;
      return keep;
    };
    if (select.loam_cloud) out.loam_cloud = cloud(nullptr, m.loam_cloud);
    if (select.sharp) out.sharp = cloud(&m.loam.sharp, m.sharp);
    if (select.less_sharp) out.less_sharp = cloud(&m.loam.less_sharp, m.less_sharp);
    if (select.flat) out.flat = cloud(&m.loam.flat, m.flat);
    if (select.less_flat) out.less_flat = cloud(&m.loam.less_flat, m.less_flat);
    f.sharp = m.loam.sharp.size();
    f.less_sharp = m.loam.less_sharp.size();
    f.flat = m.loam.flat.size();
    f.less_flat = m.loam.less_flat.size();
    f.degeneracy = m.loam.degeneracy;
  }
  f.points = static_cast<std::size_t>(msg.width) * msg.height;
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
