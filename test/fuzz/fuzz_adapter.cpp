// The PointCloud2 half of the fuzz target: the bytes as a sensor_msgs/PointCloud2 through the
// input adapter, the pipeline and every output message the nodelet publishes.
#include "fuzz_checks.hpp"
#include "ring_curvature/PrimitiveArray.h"
#include "ring_curvature/ros/frame_processor.hpp"

void ring_curvature::fuzz::fuzzAdapter(const Input& in, const Params& params)
{
  sensor_msgs::PointCloud2 msg;
  msg.width = in.width;
  msg.height = in.height;
  msg.point_step = in.point_step;
  msg.row_step = in.row_step;
  msg.is_bigendian = (in.flags & 1) != 0;
  for (const auto& f : in.fields)
  {
    sensor_msgs::PointField pf;
    pf.name = f.name;
    pf.datatype = f.datatype;
    pf.count = f.count;
    pf.offset = f.offset;
    msg.fields.push_back(pf);
  }
  msg.data = in.data;
  FrameProcessor processor(params);
  Outputs out;
  const Status st = processor.process(msg, out);
  if (!st)
  {
    require(!st.message.empty(), "a rejection names its problem");
    require(!out.labelled && !out.primitives && !out.edges && !out.planes && !out.markers,
            "a rejected frame has no output");
    return;
  }
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  checkResult(processor.result(), n);
  require(processor.summary().points == n, "summary counts every point");
  require(out.labelled && out.labelled->width == msg.width && out.labelled->height == msg.height,
          "labelled cloud has the input's shape");
  require(out.labelled->data.size() == static_cast<std::size_t>(out.labelled->row_step) * out.labelled->height,
          "labelled cloud's data matches its row_step");
  require(out.primitives && out.primitives->primitives.size() == processor.summary().primitives,
          "one primitive message per primitive");

  // The same frame with only the LOAM outputs wanted (the pipeline stops at the grid's labels).
  OutputSelection loam;
  loam.labelled = loam.primitives = loam.edges = loam.planes = loam.markers = false;
  loam.loam_cloud = loam.sharp = loam.less_sharp = loam.flat = loam.less_flat = true;
  Outputs lo;
  require(processor.process(msg, lo, loam).ok, "a frame accepted with every output is accepted with the LOAM ones");
  require(!lo.labelled && lo.loam_cloud && lo.sharp && lo.less_sharp && lo.flat && lo.less_flat, "LOAM outputs only");
  require(lo.loam_cloud->width <= n, "the LOAM cloud holds at most the input's points");
  for (const auto* c : {lo.loam_cloud.get(), lo.sharp.get(), lo.less_sharp.get(), lo.flat.get(), lo.less_flat.get()})
    require(c->data.size() == static_cast<std::size_t>(c->width) * c->point_step, "LOAM cloud's data matches its width");
  require(lo.sharp->width <= lo.less_sharp->width && lo.flat->width <= lo.less_flat->width, "sharp within less sharp, flat within less flat");

  // Deskewed (a turn at 6 m/s): the same points, moved; whatever the time field holds.
  SweepMotion motion;
  motion.rotation = {0.0, 0.0, 0.05};
  motion.translation = {0.6, 0.0, 0.0};
  processor.setSweepMotion(&motion);
  Outputs dk;
  require(processor.process(msg, dk, loam).ok, "a frame accepted is accepted deskewed");
  require(dk.loam_cloud && dk.loam_cloud->width == lo.loam_cloud->width, "deskewing keeps every point");
  processor.setSweepMotion(nullptr);
}

