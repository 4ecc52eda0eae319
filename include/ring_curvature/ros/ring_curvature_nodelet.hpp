// The ROS wrapper: subscribes to a cloud lazily, runs a FrameProcessor, publishes its outputs
// by shared pointer (zero copy inside a nodelet manager). Holds no algorithm and no static
// state: several instances in one manager (one per LiDAR) are independent.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>

#include <array>
#include <chrono>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "ring_curvature/FrameStats.h"
#include "ring_curvature/PrimitiveArray.h"
#include "ring_curvature/RingCurvatureConfig.h"
#include "ring_curvature/ros/frame_processor.hpp"
#include "ring_curvature/ros/lidar_mounting.hpp"
#include "ring_curvature/ros/odometry_motion.hpp"

namespace ring_curvature
{

/// Counters and addresses the nodelet exposes (diagnostics; the in-process tests use them to
/// prove laziness and zero copy).
struct NodeletStats
{
  std::size_t frames_received = 0, frames_processed = 0, frames_rejected = 0;
  /// Frames the input queue dropped before the callback saw them. roscpp drops silently, so they
  /// are inferred from gaps in header.seq (ROS 1 publishers number their messages); publishers
  /// that leave seq constant show 0. A drop is counted when the next frame arrives; drops just
  /// before the publisher stops are never seen.
  std::size_t frames_dropped = 0;
  bool have_last_seq = false;  ///< reset on (re)subscription: a lazy pause is not a drop
  std::uint32_t last_seq = 0;
  std::string last_error;
  const void* last_input_msg = nullptr;   ///< address of the last input message object
  const void* last_input_data = nullptr;  ///< address of the point buffer the pipeline read
  const void* last_labelled = nullptr;    ///< addresses of the last published outputs
  const void* last_primitives = nullptr;
  const void* last_edges = nullptr;
  const void* last_planes = nullptr;
};

class RingCurvatureNodelet : public nodelet::Nodelet
{
public:
  RingCurvatureNodelet() = default;
  ~RingCurvatureNodelet() override;

  NodeletStats stats() const;

private:
  void onInit() override;
  void connectCb();
  void cloudCb(const sensor_msgs::PointCloud2ConstPtr& msg);
  void reconfigureCb(RingCurvatureConfig& config, uint32_t level);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void publishStats(const std_msgs::Header& header, std::chrono::steady_clock::time_point t_entry);
  void publishOutputs(Outputs& out);
  /// The sweep's motion for the cloud with this header (false: not deskewed).
  bool deskewMotion(const std_msgs::Header& header, SweepMotion& motion);

  // Held across advertise() so connectCb never sees half-made publishers.
  std::mutex connect_mutex_;
  ros::Subscriber sub_;
  std::atomic<bool> subscribed_{false};  // sub_ as seen from other threads (diagnostics)
  ros::Publisher pub_labelled_, pub_primitives_, pub_edges_, pub_planes_, pub_markers_, pub_stats_;
  ros::Publisher pub_loam_cloud_, pub_sharp_, pub_less_sharp_, pub_flat_, pub_less_flat_;
  std::size_t degenerate_frames_ = 0;  // LOAM-assessed frames found degenerate
  int queue_size_ = 1;          // ~queue_size: input subscriber queue
  int publish_queue_size_ = 1;  // ~publish_queue_size: outgoing queue per remote subscriber
  // ~deskew_odometry: the LOAM clouds are deskewed with its mean motion over ~deskew_window
  ros::Subscriber odom_sub_;
  OdometryMotion odometry_;
  double deskew_max_age_ = 0.5;  // ~deskew_max_age [s]
  double deskew_window_ = 0.5;   // ~deskew_window [s]
  std::size_t deskewed_frames_ = 0;
  std::unique_ptr<LidarMounting> mounting_;  // ~deskew_use_tf: the odometry's child frame is not the LiDAR's
  std::string deskew_issue_;                 // why the last frame was not deskewed (tf), for diagnostics
  std::string odom_child_frame_;             // the odometry's child frame, read per frame into this

  // Guards processor_ (its parameters change from the reconfigure callback) and stats_.
  mutable std::mutex process_mutex_;
  std::unique_ptr<FrameProcessor> processor_;
  NodeletStats stats_;
  std::array<std::size_t, kNumLabels> label_totals_{};
  FrameSummary last_summary_;
  std::size_t frames_in_window_ = 0;
  ros::WallTime window_start_;

  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<RingCurvatureConfig>> reconfigure_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
};

}  // namespace ring_curvature
