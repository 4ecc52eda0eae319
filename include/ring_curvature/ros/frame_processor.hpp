// One frame in, every output message out: the code path shared by the nodelet and the offline
// process_bag tool, so that what a bag run measures is what the nodelet publishes.

#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <array>
#include <cstddef>
#include <memory>

#include "ring_curvature/loam_features.hpp"
#include "ring_curvature/params.hpp"
#include "ring_curvature/ros/primitive_message.hpp"
#include "ring_curvature/sweep_deskew.hpp"
#include "ring_curvature/types.hpp"

namespace ring_curvature
{

struct FrameResult;

/// Which outputs to build (the nodelet skips the ones nobody subscribes to).
struct OutputSelection
{
  bool labelled = true, primitives = true, edges = true, planes = true, markers = true;
  /// LOAM sets (~loam/*): every kept point, sharp, less sharp, flat, less flat.
  bool loam_cloud = false, sharp = false, less_sharp = false, flat = false, less_flat = false;
  /// Choose the LOAM sets and assess degeneracy even if none of them is published (tools).
  bool loam_report = false;
  bool anyLoam() const { return loam_cloud || sharp || less_sharp || flat || less_flat || loam_report; }
};

/// The messages of one frame; null where not selected. A cloud may be one of an earlier frame,
/// filled again, once no one but the processor held it any more.
struct Outputs
{
  sensor_msgs::PointCloud2Ptr labelled;  ///< input + curvature/smoothness/discontinuity/primitive/label
  PrimitiveArrayPtr primitives;
  sensor_msgs::PointCloud2Ptr edges;     ///< Edge and Corner points, input layout
  sensor_msgs::PointCloud2Ptr planes;    ///< Plane points, input layout
  visualization_msgs::MarkerArrayPtr markers;
  sensor_msgs::PointCloud2Ptr loam_cloud, sharp, less_sharp, flat, less_flat;  ///< sorted by ring
};

/// What diagnostics and summaries need from one frame.
struct FrameSummary
{
  std::size_t points = 0;
  std::array<std::size_t, kNumLabels> label_counts{};
  std::size_t primitives = 0;
  /// [ms] core stages (grid, features, thresholds, classification, primitives, core output),
  /// then building the ROS messages.
  double grid_ms = 0, features_ms = 0, thresholds_ms = 0, classification_ms = 0, primitives_ms = 0,
         core_output_ms = 0, messages_ms = 0;
  /// LOAM sets: whether they were chosen this frame, their sizes and the degeneracy report.
  bool loam = false;
  std::size_t sharp = 0, less_sharp = 0, flat = 0, less_flat = 0;
  DegeneracyReport degeneracy;
  double loam_ms = 0;  ///< choosing the sets (core), within messages_ms
  bool deskewed = false;  ///< the LOAM clouds' points were moved to the sensor pose at the stamp
  double coreMs() const { return grid_ms + features_ms + thresholds_ms + classification_ms + primitives_ms + core_output_ms; }
};

class FrameProcessor
{
public:
  explicit FrameProcessor(const Params& params = Params());
  ~FrameProcessor();

  /// Replaces the parameters (validated; on error the old ones stay).
  Status setParams(const Params& params);
  const Params& params() const;

  /// Reads `msg` in place (never copied), runs the pipeline and builds the selected outputs,
  /// all with msg's header. On error `out` is left empty and the status names the problem.
  Status process(const sensor_msgs::PointCloud2& msg, Outputs& out, const OutputSelection& select = {});
  Status process(const sensor_msgs::PointCloud2ConstPtr& msg, Outputs& out, const OutputSelection& select = {})
  {
    return process(*msg, out, select);
  }

  /// The sensor's motion over the next frame's sweep: its LOAM clouds (xyzi format) are then
  /// deskewed to the sensor pose at its stamp. Null: taken as they are.
  void setSweepMotion(const SweepMotion* motion);
  /// On: the LOAM clouds (xyzi format) refer to the middle of the sweep instead of the stamp:
  /// deskewed to the sensor pose there and stamped with that time, also in a frame that cannot be
  /// deskewed (no motion yet), whose points lie about the middle of the sweep on average.
  void setSweepMiddleReference(bool on);

  /// Counts and timings of the last successful frame.
  const FrameSummary& summary() const { return summary_; }
  /// The core's full result of the last successful frame (include pipeline.hpp to use it).
  const FrameResult& result() const;
  /// Address of the point buffer the last frame was read from (the zero-copy test compares it
  /// with the publisher's buffer).
  const void* lastInputData() const { return last_input_data_; }

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  FrameSummary summary_;
  const void* last_input_data_ = nullptr;
};

}  // namespace ring_curvature
